//! Sun azimuth and elevation sliders.

use render_core::scene::Sun;

use super::grid;

/// Remembers the angles it last showed for a given sun. Converting the direction back to angles
/// every frame would drift in the last digits and, at the zenith, lose the azimuth altogether;
/// so the angles are recomputed only when someone else changed the sun.
#[derive(Clone, Copy, Debug, Default)]
pub struct SunEditor {
    shown: Option<ShownSun>,
}

#[derive(Clone, Copy, Debug)]
struct ShownSun {
    sun: Sun,
    azimuth_deg: f32,
    elevation_deg: f32,
}

pub const AZIMUTH_RANGE_DEG: std::ops::RangeInclusive<f32> = 0.0..=360.0;
pub const ELEVATION_RANGE_DEG: std::ops::RangeInclusive<f32> = 0.5..=90.0;

impl SunEditor {
    pub fn ui(&mut self, ui: &mut egui::Ui, sun: &mut Sun) {
        let (mut azimuth_deg, mut elevation_deg) = match self.shown {
            Some(shown) if shown.sun == *sun => (shown.azimuth_deg, shown.elevation_deg),
            _ => sun.azimuth_elevation_deg(),
        };
        let changed = grid::facts(ui, "sun_angles", |ui| {
            let azimuth = grid::labelled(
                ui,
                "Azimuth",
                "Direction of the sun around the vertical axis, from +X towards +Z",
                |ui| {
                    ui.add(
                        egui::Slider::new(&mut azimuth_deg, AZIMUTH_RANGE_DEG)
                            .suffix("°")
                            .max_decimals(1),
                    )
                },
            );
            let elevation = grid::labelled(
                ui,
                "Elevation",
                "Height of the sun above the horizon",
                |ui| {
                    ui.add(
                        egui::Slider::new(&mut elevation_deg, ELEVATION_RANGE_DEG)
                            .suffix("°")
                            .max_decimals(1),
                    )
                },
            );
            azimuth.changed() || elevation.changed()
        });
        if changed {
            *sun = Sun::from_azimuth_elevation_deg(azimuth_deg, elevation_deg);
        }
        self.shown = Some(ShownSun {
            sun: *sun,
            azimuth_deg,
            elevation_deg,
        });
    }
}
