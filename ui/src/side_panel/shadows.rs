//! Shadow-map settings: on/off, method, resolution, biases, PCF and overlays; where settings
//! are remembered and their reset.

use render_core::frame::{FrameSettings, Method, PcfKernel};

use super::grid;
use crate::{UiAction, theme};

const MEASURE_HELP: &str = "Also render the reference shadow map of every caster, then count the visible pixels \
     whose shadow differs from it and the casters a correct map needs (the oracle). Costs a \
     second shadow pass.";

const ERROR_OVERLAY_HELP: &str = "Tint pixels whose shadow differs from the reference: red where \
     shadow is missing, blue where it is extra";

/// Shadow-map sizes offered, texels per side.
pub const RESOLUTIONS: [u32; 5] = [512, 1024, 2048, 4096, 8192];

const METHOD_HELP: &str = "How shadow casters are chosen; the names match DESIGN.md and the papers";
const RESOLUTION_HELP: &str =
    "Shadow map width and height in texels: sharper shadows for more memory and fill";
const DEPTH_BIAS_TEXELS_HELP: &str = "More constant bias, in texels of each shadow view: a \
    coarser cascade gets more, as its texels are larger";
const DEPTH_BIAS_HELP: &str = "Constant offset along the light direction that stops surfaces \
    from shadowing themselves (acne); too much detaches shadows from their casters";
const SLOPE_BIAS_HELP: &str = "Extra offset that grows with the surface's depth slope, for \
    surfaces the light grazes";
const NORMAL_OFFSET_HELP: &str = "Moves the shadow lookup along the surface normal by this many \
    shadow texels, removing acne on steep surfaces with less detachment than depth bias";
const PCF_HELP: &str = "Percentage-closer filtering: averages the shadow test over this many \
    texels around the lookup, softening shadow edges";

pub fn ui(ui: &mut egui::Ui, settings: &mut FrameSettings) {
    let shadow = &mut settings.shadow;
    ui.checkbox(&mut shadow.shadows_enabled, "Shadows enabled");
    grid::facts(ui, "shadow_settings", |ui| {
        grid::labelled(ui, "Method", METHOD_HELP, |ui| {
            egui::ComboBox::from_id_salt("shadow_method")
                .selected_text(settings.method.name())
                .show_ui(ui, |ui| {
                    for method in Method::ALL {
                        ui.selectable_value(&mut settings.method, method, method.name())
                            .on_hover_text(method.summary());
                    }
                })
                .response
        });
        grid::labelled(ui, "Resolution", RESOLUTION_HELP, |ui| {
            egui::ComboBox::from_id_salt("shadow_resolution")
                .selected_text(shadow.resolution.to_string())
                .show_ui(ui, |ui| {
                    for resolution in RESOLUTIONS {
                        ui.selectable_value(
                            &mut shadow.resolution,
                            resolution,
                            resolution.to_string(),
                        );
                    }
                })
                .response
        });
        let label = ui.label("Depth bias").on_hover_text(DEPTH_BIAS_HELP);
        ui.horizontal(|ui| {
            ui.add(
                egui::Slider::new(&mut shadow.depth_bias_m, 0.0..=1.0)
                    .logarithmic(true)
                    .smallest_positive(1e-4)
                    .suffix(" m"),
            )
            .labelled_by(label.id)
            .on_hover_text(DEPTH_BIAS_HELP);
            // Plus texels of each view: grows with a cascade's texel size.
            ui.add(
                egui::DragValue::new(&mut shadow.depth_bias_texels)
                    .range(0.0..=8.0)
                    .speed(0.05)
                    .prefix("+ ")
                    .suffix(" tx"),
            )
            .on_hover_text(DEPTH_BIAS_TEXELS_HELP);
        });
        ui.end_row();
        grid::labelled(ui, "Slope bias", SLOPE_BIAS_HELP, |ui| {
            ui.add(egui::Slider::new(&mut shadow.slope_bias, 0.0..=5.0))
        });
        grid::labelled(ui, "Normal offset", NORMAL_OFFSET_HELP, |ui| {
            ui.add(egui::Slider::new(&mut shadow.normal_offset_texels, 0.0..=4.0).suffix(" texels"))
        });
        grid::labelled(ui, "PCF kernel", PCF_HELP, |ui| {
            egui::ComboBox::from_id_salt("shadow_pcf")
                .selected_text(shadow.pcf.name())
                .show_ui(ui, |ui| {
                    for kernel in PcfKernel::ALL {
                        ui.selectable_value(&mut shadow.pcf, kernel, kernel.name());
                    }
                })
                .response
        });
    });
    // The overlays and measuring flow in rows, so the tab stays short.
    ui.horizontal_wrapped(|ui| {
        ui.checkbox(&mut settings.overlays.light_view, "Light view in corner")
            .on_hover_text("Draw the shadow map's depth over the top-left corner of the 3D view");
        ui.checkbox(&mut settings.overlays.casters, "Tint casters by outcome")
            .on_hover_text(
                "Green: drawn into the shadow map; culled: orange by the light frustum, yellow by \
                 light occlusion, magenta by the mask, the texel-exact footprint or the shadow \
                 volume; purple: excluded",
            );
        ui.checkbox(&mut settings.overlays.cascades, "Tint by cascade")
            .on_hover_text("Tint each point by the cascade (shadow view) that shades it");
        if settings.setup == render_core::frame::ShadowSetup::Volumes {
            ui.checkbox(&mut settings.overlays.fill, "Fill heat map")
                .on_hover_text(
                    "How many shadow-volume fragments each pixel took, depth test off: blue one, \
                 yellow a thousand and more",
                );
            ui.checkbox(&mut settings.overlays.volumes, "Show volumes")
                .on_hover_text(
                    "The shadow volumes in front of the surface, translucent yellow (Lloyd's \
                 Figure 1): switch the clamping to see standard against clamped volumes",
                );
        }
        ui.checkbox(&mut settings.measure, "Measure error and oracle")
            .on_hover_text(MEASURE_HELP);
        ui.add_enabled(
            settings.measure,
            egui::Checkbox::new(&mut settings.overlays.error, "Error heat map"),
        )
        .on_hover_text(ERROR_OVERLAY_HELP);
    });
}

/// Where the settings are remembered, and the button that resets them, on one line.
pub fn remembered_ui(ui: &mut egui::Ui, settings_file: Option<&str>, actions: &mut Vec<UiAction>) {
    ui.horizontal_wrapped(|ui| {
        if ui
            .button("Reset settings")
            .on_hover_text(
                "Method, shadow parameters, overlays, sun, camera and screenshot options back \
                 to their defaults; the scene stays open",
            )
            .clicked()
        {
            actions.push(UiAction::ResetSettings);
        }
        match settings_file {
            Some(path) => {
                ui.label(
                    egui::RichText::new(format!("settings are saved to {path} on close"))
                        .small()
                        .color(theme::MUTED),
                )
                .on_hover_text("Scene, camera and settings, when the window closes");
            }
            None => {
                ui.label(
                    egui::RichText::new("no config folder: nothing is remembered")
                        .small()
                        .color(theme::WARNING),
                );
            }
        }
    });
}
