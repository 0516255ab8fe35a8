//! The light's view: the shadow map's depth with the receiver mask and culled casters as an
//! inset image, its legend, and facts about the light frustum.

use render_core::frame::{FrameSettings, Overlays, legend};

use super::grid;
use crate::format::{length, metres};
use crate::{PanelInput, theme};

const VIEW_HELP: &str = "Which shadow view (cascade) the inset shows: its map, mask and culled \
    casters";

/// Size of the texture the app provides, texels.
const TEXTURE_SIZE: f32 = 256.0;

pub fn ui(ui: &mut egui::Ui, input: &PanelInput<'_>, settings: &mut FrameSettings) {
    if settings.setup == render_core::frame::ShadowSetup::Virtual {
        // The virtual maps draw their own light view: every level's pages, over the view.
        ui.label(
            "The virtual maps show their pages over the view (L, the light-view overlay): \
             each clipmap level's square, finest first, in the colours below.",
        );
        ui.checkbox(&mut settings.overlays.light_view, "Pages over the view");
        let pages = FrameSettings {
            overlays: Overlays {
                light_view: true,
                ..Overlays::default()
            },
            ..*settings
        };
        crate::legend::ui(ui, &legend(&pages));
        return;
    }
    let views = input.report.map_or(0, |r| r.views.len() as u32);
    if views > 1 {
        grid::facts(ui, "light_view_choice", |ui| {
            grid::labelled(ui, "Shadow view", VIEW_HELP, |ui| {
                ui.add(egui::Slider::new(
                    &mut settings.overlays.inset_view,
                    0..=views - 1,
                ))
            });
        });
    }
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
        // The facts of the view the inset shows.
        let shown = report
            .views
            .get(settings.overlays.inset_view as usize)
            .or(report.views.last());
        let (texel, range, whole) = shown.map_or(
            (
                report.light.texel_size_m,
                report.light.depth_range_m,
                report.light.covers_whole_scene,
            ),
            |v| (v.texel_size_m, v.depth_range_m, v.covers_whole_scene),
        );
        grid::facts(ui, "light_facts", |ui| {
            let [x, y] = texel;
            grid::row(ui, "Texel size", format!("{} × {}", length(x), metres(y)));
            grid::row(ui, "Depth range", metres(range));
            grid::row(ui, "Covers scene", if whole { "yes" } else { "no" });
        });
    }
}
