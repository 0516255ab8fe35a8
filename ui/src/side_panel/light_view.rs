//! The light's view: the shadow map's depth with the receiver mask and culled casters as an
//! inset image, and facts about the light frustum.

use super::grid;
use crate::format::{length, metres};
use crate::{PanelInput, theme};

/// Size of the texture the app provides, texels.
const TEXTURE_SIZE: f32 = 256.0;

pub fn ui(ui: &mut egui::Ui, input: &PanelInput<'_>) {
    if let Some(texture) = input.light_view {
        let side = ui.available_width().min(theme::LIGHT_VIEW_SIZE);
        let sized = egui::load::SizedTexture::new(texture, [TEXTURE_SIZE, TEXTURE_SIZE]);
        ui.add(
            egui::Image::new(sized)
                .fit_to_exact_size(egui::Vec2::splat(side))
                .alt_text("Light view"),
        );
        ui.label(
            egui::RichText::new(
                "shadow map depth, near = bright; receiver mask: BVOL blue, GEOM green, \
                 FRAG red; stripes: casters the method culled (when measuring): orange by \
                 the light frustum, yellow by light occlusion, magenta by the mask, the \
                 footprint or the shadow volume",
            )
            .small()
            .color(theme::MUTED),
        );
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
