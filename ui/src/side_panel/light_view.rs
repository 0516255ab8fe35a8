//! The light's view: the shadow map's depth with the receiver mask and culled casters as an
//! inset image, its legend, and facts about the light frustum.

use render_core::frame::{FrameSettings, Overlays, legend};

use super::grid;
use crate::format::{length, metres};
use crate::{PanelInput, theme};

/// Size of the texture the app provides, texels.
const TEXTURE_SIZE: f32 = 256.0;

pub fn ui(ui: &mut egui::Ui, input: &PanelInput<'_>, settings: &FrameSettings) {
    if let Some(texture) = input.light_view {
        let side = ui.available_width().min(theme::LIGHT_VIEW_SIZE);
        let sized = egui::load::SizedTexture::new(texture, [TEXTURE_SIZE, TEXTURE_SIZE]);
        ui.add(
            egui::Image::new(sized)
                .fit_to_exact_size(egui::Vec2::splat(side))
                .alt_text("Light view"),
        );
        // The legend of the inset alone, whatever else is on the view.
        let inset_only = FrameSettings {
            overlays: Overlays {
                light_view: true,
                ..Overlays::default()
            },
            ..*settings
        };
        crate::legend::ui(ui, &legend(&inset_only));
    } else {
        ui.label(egui::RichText::new("No light view this frame").color(theme::MUTED));
    }
    if let Some(report) = input.report {
        let light = &report.light;
        grid::facts(ui, "light_facts", |ui| {
            let [x, y] = light.texel_size_m;
            grid::row(ui, "Texel size", format!("{} × {}", length(x), metres(y)));
            grid::row(ui, "Depth range", metres(light.depth_range_m));
            grid::row(
                ui,
                "Covers scene",
                if light.covers_whole_scene {
                    "yes"
                } else {
                    "no"
                },
            );
        });
    }
}
