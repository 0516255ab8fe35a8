//! The shadow setup (one map or cascades) and the cascades' count, splits and fit, with the
//! split distances and each cascade's texel size plotted against depth (view depth, or distance from the eye for the sphere fit).

use egui_plot::{Line, Plot, PlotPoints};
use render_core::cascades::{
    CascadeDepths, CascadeFit, CascadeSelection, MAX_CASCADES, SplitScheme,
};
use render_core::frame::{FrameReport, FrameSettings, ShadowSetup};
use render_core::shadow_view::DepthMeasure;
use render_core::volumes::{VolumeClamp, VolumePassChoice};

use super::grid;
use crate::format::length;
use crate::theme;

const SETUP_HELP: &str = "single: one map fitted to the view. lispsm: one map warped by a \
    perspective in light space (Wimmer et al.), finer near the camera. cascades: the view \
    frustum cut along its depth, one map per slice (Engel), so near shadows get fine texels. \
    volumes: stencil shadow volumes, exact per pixel and without a map (Crow; Lloyd's culling \
    and clamping with any method but none). lights: the scene's lamps, a map each. virtual: \
    virtual shadow maps, a clipmap of 128-texel pages around the camera of which only those \
    visible pixels read are drawn, and kept until something moves through them";
const CLAMP_HELP: &str = "Where each shadow volume is drawn along the light. none: from the \
    caster to past the scene. continuous: only across the depths of the visible receiver \
    points under the caster (Lloyd's clamping), so no volume fills the empty space around \
    them. discrete: the view cut into slices, and per slice an interval, up to four per \
    volume; its test samples cell centres and can lose a shadow. conservative: discrete \
    clamping that never does. exact: the limit (Lloyd's CCe), each caster's own shadowed \
    receiver points found by rays on the CPU, seconds per frame. The method none draws every \
    volume; any other culls those with no visible receiver point under them";
const SLICES_HELP: &str = "Discrete clamping's slices: strips of the view between planes \
    through the eye (Lloyd's K). More slices find more empty space between receivers";
const PASS_HELP: &str = "How the stencil counts each shadow volume. auto: z-pass (counted in \
    front of the surface, no caps) where the camera's near rectangle cannot lie in the volume, \
    z-fail with caps where it can, as DOOM 3 chooses. z-pass: every volume, wrong where the \
    near plane cuts one (the camera in a shadow). z-fail: every volume, always right";
const COUNT_HELP: &str = "How many slices, each with its own map of the chosen resolution";
const SPLIT_HELP: &str = "Where the slices end: uniform, logarithmic, practical (Zhang's blend \
    of the two), geometric (Engel: each far distance a ratio times the last), manual";
const LAMBDA_HELP: &str = "The practical split's logarithmic share: 0 uniform, 1 logarithmic";
const FIRST_HELP: &str = "Where the first cascade ends";
const RATIO_HELP: &str = "Each cascade's far distance over the one before (Engel: doubled or \
    tripled)";
const MANUAL_HELP: &str = "The distances between cascades in metres, increasing: d1, d2, ...";
const FIT_HELP: &str = "tight: the slice's box in light space, the most texels but edges crawl \
    as the camera turns. sphere: a square around the slice's bounding sphere moved in whole \
    texels, its slices measured as distances from the eye, so shadows stand still as the \
    camera turns (stabilised)";
const N_HELP: &str = "Scales the warp's n from the paper's optimum (Wimmer et al. 2004, \
    (near + sqrt(near far)) / sin of the view-light angle): smaller warps harder (finer texels \
    near the camera, coarser far), larger tends to a uniform map";
const DEPTHS_HELP: &str = "scene: split where the view meets the scene, skipping cascades with \
    no visible receiver. visible: split from the nearest to the furthest visible receiver pixel \
    (sample distribution shadow maps; a frame late while the camera moves)";
const BLEND_HELP: &str = "The share of each cascade's depths, at its far end, where it blends \
    into the next; the last one fades out there (selection by depth only; 0: a hard switch)";
const SELECT_HELP: &str = "depth: each point from the cascade whose slice holds its depth (view \
    depth with the tight fit, distance from the eye with the sphere fit). \
    map: from the first cascade whose map holds all its PCF taps (the finest that has it; with \
    the sphere fit its boundaries stand still as the camera turns)";

pub fn ui(ui: &mut egui::Ui, settings: &mut FrameSettings, report: Option<&FrameReport>) {
    grid::facts(ui, "cascade_settings", |ui| {
        grid::labelled(ui, "Setup", SETUP_HELP, |ui| {
            egui::ComboBox::from_id_salt("shadow_setup")
                .selected_text(settings.setup.name())
                .show_ui(ui, |ui| {
                    for setup in ShadowSetup::ALL {
                        ui.selectable_value(&mut settings.setup, setup, setup.name());
                    }
                })
                .response
        });
        if settings.setup == ShadowSetup::Lispsm {
            grid::labelled(ui, "LiSPSM n ×", N_HELP, |ui| {
                ui.add(
                    egui::Slider::new(&mut settings.lispsm.n_scale, 0.1..=10.0).logarithmic(true),
                )
            });
        }
        if settings.setup == ShadowSetup::Volumes {
            grid::labelled(ui, "Clamping", CLAMP_HELP, |ui| {
                egui::ComboBox::from_id_salt("volume_clamp")
                    .selected_text(settings.volumes.clamp.name())
                    .show_ui(ui, |ui| {
                        for clamp in VolumeClamp::ALL {
                            ui.selectable_value(&mut settings.volumes.clamp, clamp, clamp.name());
                        }
                    })
                    .response
            });
            if matches!(
                settings.volumes.clamp,
                VolumeClamp::Discrete | VolumeClamp::Conservative
            ) {
                grid::labelled(ui, "Slices", SLICES_HELP, |ui| {
                    ui.add(egui::Slider::new(
                        &mut settings.volumes.slices,
                        1..=render_core::volumes::VolumeSettings::MAX_SLICES,
                    ))
                });
            }
            grid::labelled(ui, "Counting", PASS_HELP, |ui| {
                egui::ComboBox::from_id_salt("volume_pass")
                    .selected_text(settings.volumes.pass.name())
                    .show_ui(ui, |ui| {
                        for pass in VolumePassChoice::ALL {
                            ui.selectable_value(&mut settings.volumes.pass, pass, pass.name());
                        }
                    })
                    .response
            });
        }
        if settings.setup == ShadowSetup::Lights {
            super::lights::rows(ui, &mut settings.layered, report);
        }
        if settings.setup == ShadowSetup::Virtual {
            super::virtual_pages::rows(ui, &mut settings.virtual_maps, report);
        }
        // Many lights with the sun cascade it as the cascades setup does.
        if !settings.cascaded_sun() {
            return;
        }
        let cascades = &mut settings.cascades;
        grid::labelled(ui, "Cascades", COUNT_HELP, |ui| {
            ui.add(egui::Slider::new(&mut cascades.count, 1..=MAX_CASCADES))
        });
        let splits = &mut cascades.splits;
        grid::labelled(ui, "Split", SPLIT_HELP, |ui| {
            egui::ComboBox::from_id_salt("cascade_split")
                .selected_text(splits.scheme.name())
                .show_ui(ui, |ui| {
                    for scheme in SplitScheme::ALL {
                        ui.selectable_value(&mut splits.scheme, scheme, scheme.name());
                    }
                })
                .response
        });
        match splits.scheme {
            SplitScheme::Practical => {
                grid::labelled(ui, "Lambda", LAMBDA_HELP, |ui| {
                    ui.add(egui::Slider::new(&mut splits.lambda, 0.0..=1.0))
                });
            }
            SplitScheme::Geometric => {
                grid::labelled(ui, "First", FIRST_HELP, |ui| {
                    ui.add(
                        egui::Slider::new(&mut splits.first_m, 0.5..=500.0)
                            .logarithmic(true)
                            .suffix(" m"),
                    )
                });
                grid::labelled(ui, "Ratio", RATIO_HELP, |ui| {
                    ui.add(egui::Slider::new(&mut splits.ratio, 1.0..=8.0))
                });
            }
            SplitScheme::Manual => {
                grid::labelled(ui, "Distances", MANUAL_HELP, |ui| {
                    manual_distances(ui, &mut splits.manual_m)
                });
            }
            SplitScheme::Uniform | SplitScheme::Logarithmic => {}
        }
        // Two settings a row, so the tab fits a 720 px window.
        let fit = ui.label("Fit").on_hover_text(FIT_HELP);
        ui.horizontal(|ui| {
            combo(
                ui,
                "cascade_fit",
                &mut cascades.fit,
                &CascadeFit::ALL,
                CascadeFit::name,
            )
            .labelled_by(fit.id)
            .on_hover_text(FIT_HELP);
            let depths = ui.label("depths").on_hover_text(DEPTHS_HELP);
            combo(
                ui,
                "cascade_depths",
                &mut cascades.depths,
                &CascadeDepths::ALL,
                CascadeDepths::name,
            )
            .labelled_by(depths.id)
            .on_hover_text(DEPTHS_HELP);
        });
        ui.end_row();
        let select = ui.label("Select by").on_hover_text(SELECT_HELP);
        ui.horizontal(|ui| {
            combo(
                ui,
                "cascade_select",
                &mut cascades.selection,
                &CascadeSelection::ALL,
                CascadeSelection::name,
            )
            .labelled_by(select.id)
            .on_hover_text(SELECT_HELP);
            let blend = ui.label("blend").on_hover_text(BLEND_HELP);
            ui.add(egui::Slider::new(&mut cascades.blend, 0.0..=0.5).fixed_decimals(2))
                .labelled_by(blend.id)
                .on_hover_text(BLEND_HELP);
        });
        ui.end_row();
    });
    if settings.setup == ShadowSetup::Cascades
        && let Some(report) = report
    {
        texel_plot(ui, report, settings.cascades.count);
    }
}

/// A combo box of `choices`, named by `name`.
fn combo<T: Copy + PartialEq>(
    ui: &mut egui::Ui,
    id: &str,
    value: &mut T,
    choices: &[T],
    name: fn(T) -> &'static str,
) -> egui::Response {
    egui::ComboBox::from_id_salt(id)
        .width(70.0)
        .selected_text(name(*value))
        .show_ui(ui, |ui| {
            for &choice in choices {
                ui.selectable_value(value, choice, name(choice));
            }
        })
        .response
}

/// The manual distances as text; the settings change when the text parses.
fn manual_distances(ui: &mut egui::Ui, manual_m: &mut [f32; 7]) -> egui::Response {
    let shown: Vec<String> = manual_m
        .iter()
        .filter(|d| **d > 0.0)
        .map(|d| format!("{d}"))
        .collect();
    let mut text = shown.join(", ");
    let response = ui.text_edit_singleline(&mut text);
    if response.changed() {
        let parsed: Option<Vec<f32>> = text
            .split(',')
            .filter(|t| !t.trim().is_empty())
            .map(|t| {
                t.trim()
                    .parse::<f32>()
                    .ok()
                    .filter(|d| d.is_finite() && *d > 0.0)
            })
            .collect();
        if let Some(distances) = parsed.filter(|d| d.len() <= manual_m.len()) {
            *manual_m = [0.0; 7];
            manual_m[..distances.len()].copy_from_slice(&distances);
        }
    }
    response
}

/// Each cascade's texel size over the depths it shades: a step per cascade, the splits where
/// the steps change.
fn texel_plot(ui: &mut egui::Ui, report: &FrameReport, asked: u32) {
    let steps: Vec<(f64, f64, f64)> = report
        .views
        .iter()
        .filter_map(|v| {
            let near = f64::from(v.shades_depth_m[0].unwrap_or(0.0));
            let far = f64::from(v.shades_depth_m[1]?);
            Some((near.max(0.0), far, f64::from(v.texel_size_m[0])))
        })
        .collect();
    if steps.is_empty() {
        return;
    }
    let ends: Vec<String> = std::iter::once(steps[0].0)
        .chain(steps.iter().map(|s| s.1))
        .map(|d| length(d as f32))
        .collect();
    // Cascades whose slice holds no visible receiver are skipped (Engel).
    let drawn = report.views.len();
    let skipped = if drawn < asked as usize {
        format!(" ({drawn} of {asked} drawn)")
    } else {
        String::new()
    };
    ui.label(
        egui::RichText::new(format!("splits: {} m{skipped}", ends.join(" · ")))
            .small()
            .color(theme::MUTED),
    );
    Plot::new("cascade_texels")
        .height(theme::CASCADE_PLOT_HEIGHT)
        .x_axis_label(match report.views.first().map(|v| v.shades_by) {
            Some(DepthMeasure::EyeDistance) => "distance from the eye, m",
            _ => "view depth, m",
        })
        .y_axis_label("texel, m")
        .allow_drag(false)
        .allow_zoom(false)
        .allow_scroll(false)
        .show(ui, |plot| {
            // A flat segment per cascade, in its own colour.
            for (i, &(near, far, texel)) in steps.iter().enumerate() {
                let segment = PlotPoints::from(vec![[near, texel], [far, texel]]);
                plot.line(
                    Line::new(format!("cascade {i}"), segment)
                        .color(theme::pass_line(i))
                        .width(3.0),
                );
            }
        });
}
