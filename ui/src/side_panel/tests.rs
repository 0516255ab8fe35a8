//! The side panel driven through `egui_kittest`: what each tab shows, what clicks and keys do,
//! and an image snapshot of each tab in a 1280x720 window. Goldens live in
//! `ui/tests/snapshots/`; a missing or different one fails the test.
//! Regenerate them with `UPDATE_SNAPSHOTS=1 cargo test -p ui` and review the new images.

use egui::accesskit::Role;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable as _;
use render_core::frame::{
    CpuTimings, FrameCounts, FrameReport, FrameSettings, LightFacts, PcfKernel, ShadowSetup, Stage,
    ViewReport, pass_label,
};
use render_core::gpu::PassTiming;
use render_core::metrics::ShadowError;
use render_core::scene::{SceneFacts, Sun, Units};

use render_core::frame::Method;
use render_core::frame::compare::CompareRow;

use super::{PanelTab, SidePanel};
use crate::{PanelInput, ScreenshotSettings, UiAction};

const WIDTH: f32 = 300.0;
const HEIGHT: f32 = 2000.0;

/// What the app would hold: settings, the panel, and the facts it feeds in.
struct Lab {
    panel: SidePanel,
    settings: FrameSettings,
    screenshot: ScreenshotSettings,
    scene: SceneFacts,
    report: FrameReport,
    message: Option<String>,
    selection: Option<crate::Selection>,
    has_gpu_timestamps: bool,
    light_view: Option<egui::TextureHandle>,
    compare: Vec<CompareRow>,
    /// Draw through [`SidePanel::show`] (panel + scrolling) instead of [`SidePanel::ui`].
    in_own_panel: bool,
    lights: Vec<render_core::scene::PunctualLight>,
    /// Keys recorded so far while recording a camera path.
    recording_keys: Option<usize>,
    actions: Vec<UiAction>,
}

fn scene() -> SceneFacts {
    SceneFacts {
        name: "builtin:city".to_owned(),
        objects: 1234,
        meshes: 12,
        triangles: 1_234_567,
        casters: 1200,
        lights: 0,
        point_light: None,
        bounds_min_m: [-50.0, 0.0, -40.0],
        bounds_max_m: [50.0, 42.5, 40.0],
    }
}

fn pass(label: &str, gpu_ms: f64) -> PassTiming {
    PassTiming {
        label: label.to_owned(),
        gpu_ms,
        depth: 0,
    }
}

fn report(frame_index: u64) -> FrameReport {
    // A gentle, deterministic wobble so the plot has shape.
    let wobble = (frame_index % 7) as f64 * 0.1;
    FrameReport {
        frame_index,
        width: 1280,
        height: 720,
        counts: FrameCounts {
            casters_total: 1200,
            casters_rendered: 873,
            casters_oracle: Some(291),
            receivers_visible: None,
            objects_visible: None,
            objects_drawn_camera: 640,
            triangles_shadow: 456_789,
            triangles_camera: 345_678,
        },
        stages: vec![Stage {
            name: "light frustum".to_owned(),
            remaining: 873,
        }],
        cpu: CpuTimings {
            culling_ms: 0.42,
            encode_submit_ms: 1.25,
        },
        gpu: vec![
            pass(pass_label::CAMERA_PREPASS, 0.8 + wobble),
            pass(pass_label::SHADOW_MAP, 2.1 + wobble),
            pass(pass_label::SHADING, 1.4),
        ],
        gpu_frame_index: frame_index.checked_sub(2),
        light: LightFacts {
            texel_size_m: [0.049, 0.049],
            depth_range_m: 142.0,
            covers_whole_scene: true,
        },
        error: Some(ShadowError {
            missing_shadow_px: 12,
            extra_shadow_px: 3,
            visible_px: 65_432,
            off_edge_px: None,
        }),
        exact_error: Some(ShadowError {
            missing_shadow_px: 1_712,
            extra_shadow_px: 408,
            visible_px: 61_020,
            off_edge_px: Some(96),
        }),
        measured_frame_index: frame_index.checked_sub(1),
        ..FrameReport::default()
    }
}

impl Lab {
    fn new() -> Self {
        let mut panel = SidePanel::new();
        for i in 0..60 {
            let r = report(i);
            panel.record(i as f64 / 6.0, &r, 16.0 + (i % 5) as f64);
        }
        Self {
            panel,
            settings: FrameSettings::default(),
            screenshot: ScreenshotSettings::default(),
            scene: scene(),
            report: report(60),
            message: None,
            selection: None,
            has_gpu_timestamps: true,
            light_view: None,
            compare: Vec::new(),
            in_own_panel: false,
            lights: Vec::new(),
            recording_keys: None,
            actions: Vec::new(),
        }
    }

    fn ui(&mut self, ui: &mut egui::Ui) {
        let light_view = self
            .light_view
            .get_or_insert_with(|| {
                ui.ctx()
                    .load_texture("light_view", gradient(), egui::TextureOptions::NEAREST)
            })
            .id();
        let input = PanelInput {
            scene: &self.scene,
            lights: &self.lights,
            units: Units::default(),
            report: Some(&self.report),
            light_view: Some(light_view),
            adapter: "llvmpipe (LLVM 19.1.7, 256 bits) (Vulkan)",
            has_gpu_timestamps: self.has_gpu_timestamps,
            last_screenshot: Some("shot-0001.png"),
            message: self.message.as_deref(),
            fps: Some(59.9),
            selection: self.selection.as_ref(),
            compare: Some(&self.compare),
            settings_file: Some("/home/user/.config/shadowlab/settings.json"),
            path: crate::PathState {
                recording_keys: self.recording_keys,
                playing: None,
                last_saved: Some("shadowlab-path-1.csv"),
            },
        };
        let actions = if self.in_own_panel {
            let actions = self
                .panel
                .show(ui, &mut self.settings, &mut self.screenshot, &input);
            let view = ui.available_rect_before_wrap();
            ui.painter()
                .rect_filled(view, 0.0, egui::Color32::from_gray(60));
            self.panel.show_over_view(ui.ctx(), view, &self.settings);
            actions
        } else {
            self.panel
                .ui(ui, &mut self.settings, &mut self.screenshot, &input)
        };
        self.actions.extend(actions);
    }
}

/// A stand-in for the shadow map: bright near the top-left, dark far away.
fn gradient() -> egui::ColorImage {
    let size = 64;
    let pixels = (0..size * size)
        .map(|i| {
            let (x, y) = (i % size, i / size);
            let v = 255 - ((x + y) * 255 / (2 * size - 2)) as u8;
            egui::Color32::from_gray(v)
        })
        .collect();
    egui::ColorImage::new([size, size], pixels)
}

/// The panel with `tab` in front.
fn harness_on(mut lab: Lab, tab: PanelTab) -> Harness<'static, Lab> {
    lab.panel.open_tab(tab);
    harness(lab)
}

fn harness(lab: Lab) -> Harness<'static, Lab> {
    let mut harness = Harness::builder()
        .with_size(egui::vec2(WIDTH, HEIGHT))
        .with_context_setup(crate::theme::apply)
        .build_ui_state(|ui, lab: &mut Lab| lab.ui(ui), lab);
    harness.run();
    harness
}

#[test]
fn each_tab_shows_its_facts() {
    for (tab, labels) in [
        (
            PanelTab::Scene,
            &[
                "Objects",
                "1,234",
                "Triangles",
                "1,234,567",
                "builtin:city",
                "(-50.00, 0.00, -40.00) m",
                "100 × 42.5 × 80.0 m",
                "shot-0001.png",
            ][..],
        ),
        (
            PanelTab::Counts,
            &[
                "873 / 1,200",
                "Receivers visible",
                "…",
                "456,789",
                "345,678",
                "light frustum",
            ][..],
        ),
        (
            PanelTab::Timings,
            &[
                "GPU shadow map",
                "llvmpipe (LLVM 19.1.7, 256 bits) (Vulkan)",
                "ms over the last 10 s",
            ][..],
        ),
        (
            PanelTab::Light,
            &["0.049 × 0.049 m", "142 m", "map: near the light"][..],
        ),
    ] {
        let harness = harness_on(Lab::new(), tab);
        assert_eq!(harness.state().panel.shown_tabs(), [tab]);
        for label in labels {
            assert!(
                harness.query_by_label(label).is_some(),
                "no label {label:?} in the {tab:?} tab"
            );
        }
        // Other tabs' contents are not drawn.
        if tab != PanelTab::Scene {
            assert!(harness.query_by_label("Triangles").is_none());
        }
    }
}

#[test]
fn received_count_replaces_the_pending_mark() {
    let mut lab = Lab::new();
    lab.report.counts.receivers_visible = Some(4321);
    let harness = harness_on(lab, PanelTab::Counts);
    assert!(harness.query_by_label("4,321").is_some());
    assert!(harness.query_by_label("…").is_none());
}

#[test]
fn a_failed_shadow_pass_and_a_fallback_are_named() {
    let plain = harness_on(Lab::new(), PanelTab::Counts);
    assert!(
        plain
            .query_by_label_contains("Shadow pass failed")
            .is_none()
    );
    assert!(plain.query_by_label_contains("Fallback:").is_none());
    let mut lab = Lab::new();
    lab.report.shadow_failure =
        Some("frag: GPU culling has no scene buffers; every caster was drawn instead".into());
    lab.report.notes = vec!["geom: receiver boxes stand in for their geometry".into()];
    let failed = harness_on(lab, PanelTab::Counts);
    let failure = "Shadow pass failed: frag: GPU culling has no scene buffers";
    assert!(failed.query_by_label_contains(failure).is_some());
    assert!(
        failed
            .query_by_label_contains("Fallback: geom: receiver boxes")
            .is_some()
    );
}

#[test]
fn buttons_return_actions() {
    let mut harness = harness(Lab::new());
    for (button, action) in [
        ("Screenshot (F12)", UiAction::Screenshot),
        ("Open glTF…", UiAction::OpenFile),
        ("Frame scene (F)", UiAction::FrameScene),
        ("Reload", UiAction::ReloadScene),
        ("Record path", UiAction::RecordPath),
        ("Play path", UiAction::PlayPath),
    ] {
        harness.state_mut().actions.clear();
        harness.get_by_role_and_label(Role::Button, button).click();
        harness.run();
        assert_eq!(
            harness.state().actions,
            [action],
            "after clicking {button:?}"
        );
    }
}

#[test]
fn recording_a_path_shows_its_keys_and_stops_with_the_same_button() {
    let mut lab = Lab::new();
    lab.recording_keys = Some(12);
    let mut harness = harness(lab);
    assert!(harness.query_by_label("Record path").is_none());
    harness
        .get_by_role_and_label(Role::Button, "Stop recording (12 keys)")
        .click();
    harness.run();
    assert_eq!(harness.state().actions, [UiAction::RecordPath]);
}

#[test]
fn the_shadows_tab_names_the_settings_file_and_resets_settings() {
    let mut harness = harness_on(Lab::new(), PanelTab::Shadows);
    assert!(
        harness
            .query_by_label_contains("/home/user/.config/shadowlab/settings.json")
            .is_some()
    );
    harness
        .get_by_role_and_label(Role::Button, "Reset settings")
        .click();
    harness.run();
    assert_eq!(harness.state().actions, [UiAction::ResetSettings]);
}

#[test]
fn the_setup_combo_turns_cascades_on_and_shows_their_controls() {
    let mut harness = harness_on(Lab::new(), PanelTab::Shadows);
    assert!(
        harness.query_by_label("Lambda").is_none(),
        "no cascades, no split controls"
    );
    harness
        .get_by_role_and_label(Role::ComboBox, "Setup")
        .click();
    harness.run();
    harness
        .get_by_role(Role::ListBox)
        .get_by_label("cascades")
        .click();
    harness.run();
    assert_eq!(harness.state().settings.setup, ShadowSetup::Cascades);
    // The default split is the practical one, with its lambda.
    harness.get_by_role_and_label(Role::Slider, "Lambda");
    harness
        .get_by_role_and_label(Role::Slider, "Cascades")
        .set_value_accesskit(6.0);
    harness.run();
    assert_eq!(harness.state().settings.cascades.count, 6);
    harness
        .get_by_role_and_label(Role::ComboBox, "Split")
        .click();
    harness.run();
    harness
        .get_by_role(Role::ListBox)
        .get_by_label("geometric")
        .click();
    harness.run();
    assert_eq!(
        harness.state().settings.cascades.splits.scheme,
        render_core::cascades::SplitScheme::Geometric
    );
    harness.get_by_role_and_label(Role::Slider, "Ratio");
}

#[test]
fn the_lights_setup_chooses_how_its_maps_are_rendered_and_says_what_was_drawn() {
    let mut lab = Lab::new();
    lab.settings.setup = ShadowSetup::Lights;
    lab.report.layered = Some(render_core::technique::LayeredFacts {
        path: render_core::shadow_view::LayeredPath::Traditional,
        lights: 32,
        maps: 72,
        passes: 72,
        draws: 1080,
        triangles: 3_551_040,
        cpu_submit_ms: 0.05,
        multiview_group: 0,
        culling: render_core::shadow_view::LayerCulling::None,
        triangles_tested: 0,
    });
    let mut harness = harness_on(lab, PanelTab::Shadows);
    harness.get_by_label("32 lights, 72 maps: 72 passes, 1080 draws by traditional");
    assert!(
        harness.query_by_label("Multiview").is_none(),
        "no group to show"
    );
    harness
        .get_by_role_and_label(Role::ComboBox, "Maps by")
        .click();
    harness.run();
    harness
        .get_by_role(Role::ListBox)
        .get_by_label("atlas")
        .click();
    harness.run();
    assert_eq!(
        harness.state().settings.layered.path,
        render_core::shadow_view::LayeredPath::Atlas
    );
    // The last frame still drew the traditional way: the row says it fell back.
    harness.get_by_label("32 lights, 72 maps: 72 passes, 1080 draws by traditional (fallback)");
    // The sun joins the lights, through cascades set in the same tab.
    assert!(
        harness
            .query_by_role_and_label(Role::Slider, "Cascades")
            .is_none(),
        "no sun, no cascades"
    );
    harness.get_by_role_and_label(Role::CheckBox, "Sun").click();
    harness.run();
    assert!(harness.state().settings.layered.sun);
    harness.get_by_role_and_label(Role::Slider, "Cascades");
}

#[test]
fn the_lights_section_adds_a_spot_at_the_camera_and_removes_the_chosen_light() {
    let mut lab = Lab::new();
    lab.settings.setup = ShadowSetup::Lights;
    lab.lights = ["spot_0", "point_1"]
        .into_iter()
        .map(|name| render_core::scene::PunctualLight {
            name: name.to_owned(),
            position: glam::Vec3::new(1.0, 4.0, 2.0),
            kind: render_core::scene::LightKind::Point,
            color: [1.0; 3],
            intensity: 1000.0,
            range: None,
        })
        .collect();
    let mut harness = harness_on(lab, PanelTab::Shadows);
    harness.get_by_role_and_label(Role::ComboBox, "Edit");
    harness.get_by_label("Position");
    harness.get_by_label("Add spot at camera").click();
    harness.run();
    harness.get_by_label("Remove").click();
    harness.run();
    let actions = &harness.state().actions;
    assert!(actions.contains(&UiAction::AddSpotLight), "{actions:?}");
    assert!(actions.contains(&UiAction::RemoveLight(0)), "{actions:?}");
    assert!(
        !actions.iter().any(|a| matches!(a, UiAction::MoveLight(..))),
        "nothing moved: {actions:?}"
    );
}

#[test]
fn the_units_combo_reads_a_file_again_in_another_unit() {
    let mut lab = Lab::new();
    lab.scene.name = "scenes/diorama.gltf".into();
    let mut harness = harness(lab);
    // The Scene section comes first: its combo box is the unit.
    harness
        .get_all_by_role(Role::ComboBox)
        .next()
        .expect("the units combo box")
        .click();
    harness.run();
    harness.get_by_label("cm").click();
    harness.run();
    assert_eq!(
        harness.state().actions,
        [UiAction::SetUnits(Units::Centimetres)]
    );
}

#[test]
fn each_method_says_what_it_does_and_cites_its_paper() {
    let mut harness = harness_on(Lab::new(), PanelTab::Shadows);
    harness
        .get_all_by_role(Role::ComboBox)
        .next()
        .expect("the method combo box")
        .click();
    harness.run();
    harness.get_by_label("frag").hover();
    harness.run();
    assert!(
        harness
            .query_by_label_contains("Bittner et al. 2011, section 4.4")
            .is_some(),
        "the tooltip of frag cites its section"
    );
}

#[test]
fn show_puts_a_scrolling_panel_on_the_left() {
    let mut lab = Lab::new();
    lab.in_own_panel = true;
    let mut harness = Harness::builder()
        .with_size(egui::vec2(900.0, 500.0))
        .with_context_setup(crate::theme::apply)
        .build_ui_state(|ui, lab: &mut Lab| lab.ui(ui), lab);
    harness.run();

    let scene_name = harness.get_by_label("builtin:city").rect();
    assert!(scene_name.left() < crate::theme::SIDE_PANEL_WIDTH);
    let button = harness.get_by_role_and_label(Role::Button, "Screenshot (F12)");
    assert!(button.rect().top() > 500.0, "the button starts out of view");
    button.scroll_to_me();
    harness.run();
    let button = harness.get_by_role_and_label(Role::Button, "Screenshot (F12)");
    assert!(button.rect().bottom() <= 500.0, "scrolled into view");
    button.click();
    harness.run();
    assert_eq!(harness.state().actions, [UiAction::Screenshot]);
}

#[test]
fn no_clicks_no_actions_and_no_setting_changes() {
    let mut harness = harness(Lab::new());
    harness.run_steps(5);
    let lab = harness.state();
    assert!(lab.actions.is_empty());
    assert_eq!(lab.settings, FrameSettings::default());
    assert_eq!(lab.screenshot, ScreenshotSettings::default());
}

#[test]
fn pcf_kernel_combo_edits_settings() {
    let mut harness = harness_on(Lab::new(), PanelTab::Shadows);
    harness
        .get_by_role_and_label(Role::ComboBox, "PCF kernel")
        .click();
    harness.run();
    harness
        .get_by_role(Role::ListBox)
        .get_by_label("5x5")
        .click();
    harness.run();
    assert_eq!(harness.state().settings.shadow.pcf, PcfKernel::K5x5);
}

#[test]
fn resolution_combo_edits_settings() {
    let mut harness = harness_on(Lab::new(), PanelTab::Shadows);
    harness
        .get_by_role_and_label(Role::ComboBox, "Resolution")
        .click();
    harness.run();
    harness
        .get_by_role(Role::ListBox)
        .get_by_label("4096")
        .click();
    harness.run();
    assert_eq!(harness.state().settings.shadow.resolution, 4096);
}

#[test]
fn the_selected_object_says_why_it_was_culled() {
    let mut lab = Lab::new();
    assert!(
        harness(Lab::new())
            .query_by_label("Selected object")
            .is_none()
    );
    lab.selection = Some(crate::Selection {
        name: "block_3_7/building_2".into(),
        casts_shadow: true,
        receives_shadow: true,
        visible: true,
        shadow_map: "light frustum".into(),
        oracle: Some(false),
        volume_intervals: Some(vec![[0.0, 12.54], [30.06, 31.0]]),
    });
    let harness = harness(lab);
    harness.get_by_label("block_3_7/building_2");
    harness.get_by_label("Needed (oracle)");
    harness.get_by_label("Volume intervals");
    harness.get_by_label("0.0-12.5 m, 30.1-31.0 m");
    assert!(harness.query_all_by_label("light frustum").count() >= 1);
}

#[test]
fn oracle_tightness_and_error_are_shown_when_measured() {
    let harness = harness_on(Lab::new(), PanelTab::Counts);
    harness.get_by_label("291");
    harness.get_by_label("3.00");
    harness.get_by_label("Missing shadow px");
    harness.get_by_label("Extra shadow px");
    harness.get_by_label("65,432");
}

#[test]
fn checkboxes_edit_settings() {
    let mut harness = harness_on(Lab::new(), PanelTab::Shadows);
    harness.get_by_label("Shadows enabled").click();
    harness.get_by_label("Light view in corner").click();
    harness.get_by_label("Tint casters by outcome").click();
    harness.get_by_label("Measure error and oracle").click();
    harness.run();
    harness.get_by_label("Error heat map").click();
    harness.run();
    harness.state_mut().panel.open_tab(PanelTab::Scene);
    harness.run();
    harness.get_by_label("Include panel").click();
    harness.get_by_label("Animate dynamic objects").click();
    harness.run();
    let lab = harness.state();
    assert!(!lab.settings.shadow.shadows_enabled);
    assert!(lab.settings.overlays.light_view);
    assert!(lab.settings.overlays.casters);
    assert!(lab.settings.measure);
    assert!(lab.settings.animate);
    assert!(
        lab.settings.overlays.error,
        "the heat map is enabled once measuring is on"
    );
    assert!(lab.screenshot.include_panel);
}

#[test]
fn sun_sliders_edit_the_sun_and_idle_frames_keep_it_exact() {
    let mut lab = Lab::new();
    lab.settings.sun = Sun::from_azimuth_elevation_deg(123.4, 20.0);
    let before = lab.settings.sun;
    let mut harness = harness(lab);
    harness.run_steps(5);
    assert_eq!(
        harness.state().settings.sun,
        before,
        "idle frames rewrote the sun"
    );

    // Up to the zenith, where the direction alone has no azimuth, and back down:
    // the azimuth the user set survives.
    harness
        .get_by_role_and_label(Role::Slider, "Elevation")
        .set_value_accesskit(90.0);
    harness.run();
    let at_zenith = harness.state().settings.sun;
    assert!(at_zenith.direction_to_sun.y > 0.999_999);
    harness.run_steps(5);
    assert_eq!(harness.state().settings.sun, at_zenith);

    harness
        .get_by_role_and_label(Role::Slider, "Elevation")
        .set_value_accesskit(30.0);
    harness.run();
    let (azimuth, elevation_deg) = harness.state().settings.sun.azimuth_elevation_deg();
    assert!(
        (elevation_deg - 30.0).abs() < 1e-3,
        "elevation {elevation_deg}"
    );
    assert!((azimuth - 123.4).abs() < 1e-3, "azimuth {azimuth}");

    harness
        .get_by_role_and_label(Role::Slider, "Azimuth")
        .set_value_accesskit(200.0);
    harness.run();
    let (azimuth, _) = harness.state().settings.sun.azimuth_elevation_deg();
    assert!((azimuth - 200.0).abs() < 1e-3, "azimuth {azimuth}");
}

#[test]
fn message_is_shown_only_when_present() {
    let text = "scene.glb: not a valid glTF (unexpected end of file)";
    let mut harness = harness(Lab::new());
    assert!(
        harness
            .query_by_label_contains("not a valid glTF")
            .is_none()
    );
    harness.state_mut().message = Some(text.to_owned());
    harness.run();
    assert!(harness.query_by_label(text).is_some());
}

#[test]
fn missing_gpu_timestamps_are_explained() {
    let mut lab = Lab::new();
    lab.has_gpu_timestamps = false;
    let harness = harness_on(lab, PanelTab::Timings);
    assert!(
        harness
            .query_by_label("GPU timestamps not available on this adapter")
            .is_some()
    );
    assert!(harness.query_by_label("GPU shadow map").is_none());
}

#[test]
fn record_keeps_only_the_last_ten_seconds() {
    let mut panel = SidePanel::new();
    let r = report(0);
    // 30 s at 60 fps.
    for i in 0..1800 {
        panel.record(f64::from(i) / 60.0, &r, 16.7);
    }
    let history = panel.history();
    assert!(history.span_s() <= crate::TimingHistory::WINDOW_S);
    assert!(history.len() <= 601, "{} samples", history.len());
    assert!(history.len() >= 600, "{} samples", history.len());
    assert_eq!(history.pass_series().len(), 3);
}

/// Every method's row, as "compare all" lists them.
fn compare_rows() -> Vec<CompareRow> {
    Method::ALL
        .into_iter()
        .enumerate()
        .map(|(i, method)| CompareRow {
            method,
            casters_rendered: 420 - 30 * i as u32,
            triangles: 42_000 - 3_000 * i as u64,
            casters_oracle: Some(75),
            error_px: Some(if method.may_err() { 37 } else { 0 }),
            shadow_ms: Some(2.5 - 0.1 * i as f64),
            culling_ms: Some(0.4),
            stale: false,
        })
        .collect()
}

/// The window's layout: the panel at its default width beside the view, at 1280x720.
fn window_on(tab: PanelTab, setup: impl FnOnce(&mut Lab)) -> Harness<'static, Lab> {
    let mut lab = Lab::new();
    lab.in_own_panel = true;
    lab.compare = compare_rows();
    lab.settings.compare_all = true;
    lab.settings.measure = true;
    lab.settings.method = Method::Bvol;
    lab.settings.overlays.light_view = true;
    lab.settings.overlays.casters = true;
    lab.selection = Some(crate::Selection {
        name: "block_3_7/building_2".into(),
        casts_shadow: true,
        receives_shadow: true,
        visible: true,
        shadow_map: "light frustum".into(),
        oracle: Some(false),
        volume_intervals: None,
    });
    // Every pass a measured GPU-culled frame times, the culling steps inside their scope.
    lab.report.gpu = [
        (pass_label::CAMERA_PREPASS, 0),
        (pass_label::CULLING, 0),
        (pass_label::culling::MASKS, 1),
        (pass_label::culling::PYRAMIDS, 1),
        (pass_label::culling::CASTER_TESTS, 1),
        (pass_label::culling::FOOTPRINTS, 1),
        (pass_label::SHADOW_MAP, 0),
        (pass_label::REFERENCE_MAP, 0),
        (pass_label::SHADING, 0),
        (pass_label::OVERLAYS, 0),
    ]
    .into_iter()
    .map(|(label, depth)| PassTiming {
        depth,
        ..pass(label, 0.5)
    })
    .collect();
    // Four cascades, as the street view gives them.
    lab.settings.setup = ShadowSetup::Cascades;
    lab.report.views = [
        (None, 9.5, 0.08),
        (Some(9.5), 38.0, 0.16),
        (Some(38.0), 150.0, 0.32),
        (Some(150.0), 600.0, 1.26),
    ]
    .into_iter()
    .enumerate()
    .map(|(i, (near, far, texel))| ViewReport {
        name: format!("cascade {i}"),
        casters_rendered: 20 + 10 * i as u32,
        casters_oracle: Some(15 + 7 * i as u32),
        texel_size_m: [texel, texel],
        shades_depth_m: [near, Some(far)],
        undersampling: Some(render_core::metrics::Undersampling {
            median_octaves: 0.0,
            p95_octaves: 0.25 * i as f32,
            pixels: 1000,
        }),
        ..ViewReport::default()
    })
    .collect();
    setup(&mut lab);
    lab.panel.open_tab(tab);
    let mut harness = Harness::builder()
        .with_size(egui::vec2(1280.0, 720.0))
        .with_context_setup(crate::theme::apply)
        .build_ui_state(|ui, lab: &mut Lab| lab.ui(ui), lab);
    harness.run();
    harness
}

/// Each tab in a 1280x720 window, rendered with wgpu (lavapipe on CPU-only machines:
/// `WGPU_BACKEND=vulkan XDG_RUNTIME_DIR=$(mktemp -d) cargo test -p ui`), with the legend of
/// the overlays over the view. Each tab's last widget ends above the window's bottom: nothing
/// needs scrolling.
#[test]
fn each_tab_fits_a_1280x720_window_and_matches_its_snapshot() {
    let mut snapshots = egui_kittest::SnapshotResults::new();
    for (tab, last) in [
        (PanelTab::Scene, "Screenshot (F12)"),
        (PanelTab::Shadows, "Reset settings"),
        (PanelTab::Compare, "oracle"),
        (PanelTab::Counts, "cascade 3"),
        (PanelTab::Timings, "ms over the last 10 s"),
        (PanelTab::Light, "Covers scene"),
    ] {
        let mut harness = window_on(tab, |_| {});
        harness.snapshot(format!("tab_{}", tab.title().to_lowercase()));
        snapshots.extend_harness(&mut harness);
        let bottom = harness
            .query_all_by_label(last)
            .map(|node| node.rect().bottom())
            .fold(f32::MIN, f32::max);
        let plot = if tab == PanelTab::Timings {
            crate::theme::PLOT_HEIGHT
        } else {
            0.0
        };
        assert!(bottom > 0.0, "no {last:?} in the {tab:?} tab");
        let panel_right = crate::theme::SIDE_PANEL_WIDTH;
        for title in PanelTab::ALL
            .map(PanelTab::title)
            .into_iter()
            .chain(["cull\nms"])
        {
            if let Some(node) = harness.query_by_label(title) {
                assert!(
                    node.rect().right() <= panel_right,
                    "{title:?} ends at {} px, right of the panel",
                    node.rect().right()
                );
            } else {
                assert!(
                    title == "cull\nms" && tab != PanelTab::Compare,
                    "no {title:?}"
                );
            }
        }
        assert!(
            bottom + plot <= 720.0,
            "the {tab:?} tab ends at {} px, below the window",
            bottom + plot
        );
    }
    snapshots.unwrap();
}

#[test]
fn the_help_overlay_lists_every_shortcut_and_matches_its_snapshot() {
    let mut harness = window_on(PanelTab::Scene, |_| {});
    assert!(harness.query_by_label("Keyboard shortcuts (F1)").is_none());
    harness.key_press(egui::Key::F1);
    harness.run();
    assert!(harness.state().panel.help_open());
    for (keys, what) in crate::shortcuts::help() {
        assert!(harness.query_by_label(&keys).is_some(), "{keys} not listed");
        assert!(harness.query_by_label(what).is_some(), "{what} not listed");
    }
    harness.snapshot("help_overlay");
    harness.key_press(egui::Key::F1);
    harness.run();
    assert!(!harness.state().panel.help_open());
}

#[test]
fn keys_switch_methods_overlays_and_tabs() {
    let mut harness = window_on(PanelTab::Scene, |lab| {
        lab.settings = FrameSettings::default();
    });
    let first = Method::ALL[0];
    assert_eq!(harness.state().settings.method, first);
    harness.key_press(egui::Key::M);
    harness.run();
    assert_eq!(harness.state().settings.method, Method::ALL[1]);
    harness.key_press_modifiers(egui::Modifiers::SHIFT, egui::Key::M);
    harness.key_press_modifiers(egui::Modifiers::SHIFT, egui::Key::M);
    harness.run();
    assert_eq!(
        harness.state().settings.method,
        Method::ALL[Method::ALL.len() - 1],
        "back past the first method to the last"
    );
    for key in [egui::Key::L, egui::Key::C, egui::Key::H, egui::Key::K] {
        harness.key_press(key);
    }
    harness.run();
    let settings = harness.state().settings;
    assert!(settings.overlays.light_view && settings.overlays.casters);
    assert!(
        settings.overlays.error && settings.measure,
        "H measures too"
    );
    assert!(settings.compare_all);
    harness.key_press(egui::Key::F4);
    harness.run();
    assert_eq!(harness.state().panel.shown_tabs(), [PanelTab::Compare]);
    harness.key_press(egui::Key::F12);
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::O);
    harness.run();
    assert_eq!(
        harness.state().actions,
        [UiAction::Screenshot, UiAction::OpenFile]
    );
    // The legend names what the overlays now show, in the view.
    assert!(harness.query_by_label("Casters tint").is_some());
    assert!(harness.query_by_label("shadow missing").is_some());
}

#[test]
fn keys_typed_into_a_text_field_are_not_shortcuts() {
    let mut harness = window_on(PanelTab::Scene, |lab| {
        lab.settings = FrameSettings::default();
    });
    harness
        .get_by_role_and_label(Role::TextInput, "Folder")
        .focus();
    harness.run();
    harness.key_press(egui::Key::M);
    harness.key_press(egui::Key::L);
    harness.run();
    assert_eq!(harness.state().settings, FrameSettings::default());
}

#[test]
fn compare_all_switches_on_and_lists_every_row() {
    let mut lab = Lab::new();
    lab.compare = [
        (Method::Ref, 420, Some(0)),
        (Method::Frag, 150, Some(0)),
        (Method::DrProgressive, 120, Some(37)),
    ]
    .into_iter()
    .map(|(method, casters, error)| CompareRow {
        method,
        casters_rendered: casters,
        triangles: u64::from(casters) * 100,
        casters_oracle: Some(75),
        error_px: error,
        shadow_ms: Some(2.5),
        culling_ms: Some(0.4),
        stale: false,
    })
    .collect();
    let mut harness = harness_on(lab, PanelTab::Compare);
    // Off: the table is hidden even with rows.
    assert!(harness.query_by_label("dr-progressive").is_none());
    harness.get_by_label("Compare all methods").click();
    harness.run();
    assert!(harness.state().settings.compare_all);
    for label in [
        "ref",
        "frag",
        "dr-progressive",
        "× oracle",
        "2.00",
        "5.60",
        "37",
    ] {
        assert!(
            harness.query_by_label(label).is_some(),
            "'{label}' is not shown"
        );
    }
    // Beside the table, each row as a point of speed against error.
    assert!(
        harness
            .query_by_label("speed against error: shadow + cull ms (x), error px (y)")
            .is_some()
    );
    let rows = &harness.state().compare;
    let points: Vec<_> = rows
        .iter()
        .filter_map(super::compare::speed_and_error)
        .collect();
    assert_eq!(points.len(), 3);
    for (point, error) in points.iter().zip([0.0, 0.0, 37.0]) {
        assert!(
            (point[0] - 2.9).abs() < 1e-9 && (point[1] - error).abs() < 1e-9,
            "{point:?}"
        );
    }
}

#[test]
fn the_virtual_setup_sets_its_pool_and_cache_and_says_what_its_pages_did() {
    let mut lab = Lab::new();
    lab.settings.setup = ShadowSetup::Virtual;
    lab.report.virtual_pages = Some(render_core::technique::VirtualPages {
        pages_marked: 140,
        pages_resident: 1024,
        pages_rendered: 12,
        pages_refused: 3,
        cache_hit_rate: Some(0.893),
        pages_evicted: 5,
        pool_pages: 1024,
        pool_mib: 64.0,
        levels: 16,
        cache: true,
        separate_static: true,
        pages_refreshed: 31,
        receiver_mask: true,
        caster_pages_masked: 700,
        caster_pages: 2500,
        static_occlusion: true,
        moved_pages_occluded: 254,
        caster_pages_occluded: 72,
        ..Default::default()
    });
    let mut harness = harness_on(lab, PanelTab::Shadows);
    harness.get_by_label("140 marked, 1,024 resident, 12 drawn");
    harness.get_by_label("89% of the marked pages were kept");
    harness.get_by_label("31 pages' movable casters alone drawn");
    harness.get_by_label("2,500 (caster, page) draws, 700 left out by the receiver mask");
    harness.get_by_label("254 pages kept fresh behind static casters, 72 draws left out");
    harness.get_by_label("3 refused (pool full), 5 evicted");
    harness.get_by_label("100% of 1024 pages");
    harness.get_by_label("64 MiB");
    harness.get_by_role_and_label(Role::Slider, "Level bias");
    harness
        .get_by_role_and_label(Role::CheckBox, "Cache")
        .click();
    harness.run();
    assert!(!harness.state().settings.virtual_maps.cache);
    harness
        .get_by_role_and_label(Role::CheckBox, "Static apart")
        .click();
    harness.run();
    assert!(harness.state().settings.virtual_maps.separate_static);
    // Static occlusion, on by default, applies with static casters apart.
    assert!(harness.state().settings.virtual_maps.static_occlusion);
    harness
        .get_by_role_and_label(Role::CheckBox, "Static occlusion")
        .click();
    harness.run();
    assert!(!harness.state().settings.virtual_maps.static_occlusion);
}

#[test]
fn the_light_tab_of_the_virtual_maps_turns_their_page_view_on_and_names_its_colours() {
    let mut lab = Lab::new();
    lab.settings.setup = ShadowSetup::Virtual;
    let mut harness = harness_on(lab, PanelTab::Light);
    harness.get_by_label("refused: the pool is full");
    assert!(
        harness.query_by_label("Light view").is_none(),
        "no stale inset image"
    );
    harness
        .get_by_role_and_label(Role::CheckBox, "Pages over the view")
        .click();
    harness.run();
    assert!(harness.state().settings.overlays.light_view);
}
