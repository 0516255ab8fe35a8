//! The sweeps the papers' figures use, each a section of its family: the rows at each value
//! of the swept parameter, a line per method (or path) across the values, one plot per
//! measure the figure shows.
//!
//! - shadow-map size, Bittner et al.'s Table 4, and sun elevation, their Figure 7;
//! - cascade counts (after the single map and LiSPSM) and split schemes;
//! - shadow volumes' slicing planes, Lloyd et al.'s Figure 9;
//! - number of maps, Rákos's Figure 19.3 (the scene's first N lights, each path).

use render_core::frame::{FrameSettings, Method, ShadowSetup};
use render_core::scene::LightKind;
use render_core::shadow_view::LayeredPath;

use super::families::Family;
use crate::bench::{BenchRow, SweepValues, median, sweep_settings};
use crate::cli::Sweep;

/// A parameter a report sweeps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReportSweep {
    Resolution,
    Elevation,
    Cascades,
    Splits,
    Slices,
    Maps,
}

/// One row of a sweep: its value of the parameter (the x axis), its line, its settings.
pub struct SweepRow {
    pub point: String,
    pub series: String,
    pub settings: FrameSettings,
}

/// What a sweep's plot shows on its y axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Measure {
    /// The shadow passes' and the culling's GPU time, ms.
    ShadowGpuMs,
    /// The CPU time of a frame, ms.
    FrameCpuMs,
    /// Error pixels: against the exact shadow where every row has it, else the reference.
    Error,
    CastersDrawn,
    UndersamplingP95,
    /// Shadow volumes' fill, millions of fragments (median frame).
    FillM,
    /// Shadow volumes' stencil pass, GPU ms (median frame).
    VolumePassMs,
}

/// The methods the culling sweeps compare: the frustum alone, Bittner's FRAG, DigitalRune's
/// conservative test, and the oracle.
const CULLING_METHODS: [Method; 4] = [
    Method::Vfc,
    Method::Frag,
    Method::DrConservative,
    Method::Oracle,
];

/// How many of the scene's lights the maps sweep lights.
const LIGHT_COUNTS: [usize; 6] = [1, 2, 4, 8, 16, 32];

impl ReportSweep {
    pub const ALL: [Self; 6] = [
        Self::Resolution,
        Self::Elevation,
        Self::Cascades,
        Self::Splits,
        Self::Slices,
        Self::Maps,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Self::Resolution => "resolution",
            Self::Elevation => "elevation",
            Self::Cascades => "cascades",
            Self::Splits => "splits",
            Self::Slices => "slices",
            Self::Maps => "maps",
        }
    }

    /// The family whose section it is part of.
    pub fn family(self) -> Family {
        match self {
            Self::Resolution | Self::Elevation => Family::Culling,
            Self::Cascades | Self::Splits => Family::Setups,
            Self::Slices => Family::Volumes,
            Self::Maps => Family::Lights,
        }
    }

    /// Its title before the colon, what its rows are after.
    pub fn description(self) -> &'static str {
        match self {
            Self::Resolution => {
                "Shadow-map size (Bittner et al.'s Table 4): vfc, frag, dr-conservative and \
                 the oracle on maps of 512, 1024 and 2048 texels"
            }
            Self::Elevation => {
                "Sun elevation (Bittner et al.'s Figure 7): the same methods with the sun at \
                 10, 30, 50 and 70 degrees, the view's azimuth"
            }
            Self::Cascades => {
                "Cascade counts: the single map, LiSPSM, then 1, 2, 4 and 8 cascades, with the \
                 view's method and split scheme"
            }
            Self::Splits => {
                "Split schemes: the view's cascades split uniformly, logarithmically, by Zhang's \
                 practical blend and by Engel's geometric series"
            }
            Self::Slices => {
                "Slicing planes (Lloyd et al.'s Figure 9): standard shadow volumes, then CC \
                 shadow volumes with conservative clamping over 1 to 32 slices"
            }
            Self::Maps => {
                "Number of maps (Rákos's Figure 19.3): the scene's first 1 to 32 lights, each \
                 path"
            }
        }
    }

    /// The x axis's name.
    pub fn x_desc(self) -> &'static str {
        match self {
            Self::Resolution => "shadow-map size, texels",
            Self::Elevation => "sun elevation",
            Self::Cascades => "shadow setup",
            Self::Splits => "split scheme",
            Self::Slices => "slices",
            Self::Maps => "lights (maps)",
        }
    }

    /// The plots, a measure each.
    pub fn measures(self) -> &'static [Measure] {
        use Measure::{
            CastersDrawn, Error, FillM, FrameCpuMs, ShadowGpuMs, UndersamplingP95, VolumePassMs,
        };
        match self {
            Self::Resolution => &[ShadowGpuMs, Error],
            Self::Elevation => &[CastersDrawn, ShadowGpuMs],
            Self::Cascades | Self::Splits => &[UndersamplingP95, Error],
            Self::Slices => &[FillM, VolumePassMs],
            Self::Maps => &[ShadowGpuMs, FrameCpuMs],
        }
    }

    /// The rows, from the view's settings; `lights` are the scene's lights' kinds.
    pub fn rows(self, base: &FrameSettings, lights: &[LightKind]) -> anyhow::Result<Vec<SweepRow>> {
        let base = *base;
        let values = SweepValues {
            resolutions: vec![512, 1024, 2048],
            elevations: vec![10.0, 30.0, 50.0, 70.0],
            cascade_counts: vec![1, 2, 4, 8],
            lambdas: Vec::new(),
        };
        let swept = |sweep| sweep_settings(sweep, &base, &values);
        let one_line = |sweep, series: String| -> anyhow::Result<Vec<SweepRow>> {
            Ok(swept(sweep)?
                .into_iter()
                .map(|(point, settings)| SweepRow {
                    point,
                    series: series.clone(),
                    settings,
                })
                .collect())
        };
        let by_method = |sweep| -> anyhow::Result<Vec<SweepRow>> {
            Ok(swept(sweep)?
                .into_iter()
                .flat_map(|(point, settings)| {
                    CULLING_METHODS.into_iter().map(move |method| SweepRow {
                        point: point.clone(),
                        series: method.name().to_owned(),
                        settings: FrameSettings {
                            setup: ShadowSetup::Single,
                            method,
                            ..settings
                        },
                    })
                })
                .collect())
        };
        match self {
            Self::Resolution => by_method(Sweep::Resolution),
            Self::Elevation => by_method(Sweep::Elevation),
            Self::Cascades => one_line(Sweep::Cascades, format!("culling: {}", base.method.name())),
            Self::Splits => one_line(Sweep::Splits, format!("culling: {}", base.method.name())),
            Self::Slices => {
                let base = FrameSettings {
                    method: Method::Vfc,
                    ..base
                };
                Ok(sweep_settings(Sweep::Slices, &base, &values)?
                    .into_iter()
                    .map(|(point, settings)| SweepRow {
                        point,
                        series: format!("clamp {}", settings.volumes.clamp.name()),
                        settings,
                    })
                    .collect())
            }
            Self::Maps => Ok(maps_rows(&base, lights)),
        }
    }
}

/// Each number of the scene's lights (up to all of them), each path.
fn maps_rows(base: &FrameSettings, lights: &[LightKind]) -> Vec<SweepRow> {
    let base = *base;
    let mut counts: Vec<usize> = LIGHT_COUNTS.iter().map(|&n| n.min(lights.len())).collect();
    counts.dedup();
    counts
        .into_iter()
        .filter(|&n| n > 0)
        .flat_map(|n| {
            let maps: usize = lights[..n]
                .iter()
                .map(|kind| match kind {
                    LightKind::Point => render_core::geom::CUBE_FACES.len(),
                    LightKind::Spot { .. } => 1,
                })
                .sum();
            LayeredPath::ALL.into_iter().map(move |path| {
                let mut settings = FrameSettings {
                    setup: ShadowSetup::Lights,
                    method: Method::Vfc,
                    ..base
                };
                settings.layered.path = path;
                settings.layered.lights = n as u32;
                SweepRow {
                    point: format!("{n} ({maps})"),
                    series: path.name().to_owned(),
                    settings,
                }
            })
        })
        .collect()
}

impl Measure {
    /// Its value in a row; `exact`: the error is against the exact shadow.
    pub fn value(self, row: &BenchRow, exact: bool) -> Option<f64> {
        match self {
            Self::ShadowGpuMs => super::shadow_gpu_ms(row),
            Self::FrameCpuMs => Some(row.frame_ms),
            Self::Error if exact => row.exact_error.0,
            Self::Error => Some(f64::from(row.error_px_max)),
            Self::CastersDrawn => Some(row.casters_drawn),
            Self::UndersamplingP95 => row.undersampling.1,
            Self::FillM => row.fill_m.0,
            Self::VolumePassMs => median(row.volume_pass_frames.clone()),
        }
    }

    /// Its name in file names.
    pub fn name(self) -> &'static str {
        match self {
            Self::ShadowGpuMs => "shadow-gpu",
            Self::FrameCpuMs => "frame-cpu",
            Self::Error => "error",
            Self::CastersDrawn => "casters",
            Self::UndersamplingP95 => "undersampling",
            Self::FillM => "fill",
            Self::VolumePassMs => "stencil-gpu",
        }
    }

    /// The y axis's name.
    pub fn y_desc(self, exact: bool) -> &'static str {
        match self {
            Self::ShadowGpuMs => "shadow passes + culling, GPU ms",
            Self::FrameCpuMs => "frame, CPU ms",
            Self::Error if exact => "error px against the exact shadow (median)",
            Self::Error => "error px against the reference (worst frame)",
            Self::CastersDrawn => "casters drawn (median)",
            Self::UndersamplingP95 => "undersampling p95, octaves",
            Self::FillM => "fill, M fragments (median)",
            Self::VolumePassMs => "stencil pass, GPU ms (median)",
        }
    }
}

/// `--sweeps`: a comma list, `all` or `none`; a sweep runs only where its family does.
pub fn parse(list: &str, families: &[Family]) -> anyhow::Result<Vec<ReportSweep>> {
    let wanted: Vec<ReportSweep> = match list.trim() {
        "all" => ReportSweep::ALL.to_vec(),
        "none" => Vec::new(),
        list => list
            .split(',')
            .map(|name| {
                let name = name.trim();
                ReportSweep::ALL
                    .into_iter()
                    .find(|s| s.name() == name)
                    .ok_or_else(|| {
                        anyhow::anyhow!(
                            "--sweeps: '{name}' is not a sweep (resolution, elevation, \
                             cascades, splits, slices, maps, all or none)"
                        )
                    })
            })
            .collect::<anyhow::Result<_>>()?,
    };
    Ok(wanted
        .into_iter()
        .filter(|s| families.contains(&s.family()))
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sweeps_parse_and_follow_their_families() {
        let all = parse("all", &[Family::Culling, Family::Volumes]).unwrap();
        assert_eq!(
            all,
            [
                ReportSweep::Resolution,
                ReportSweep::Elevation,
                ReportSweep::Slices
            ]
        );
        assert!(parse("none", &Family::ALL).unwrap().is_empty());
        let err = parse("slices,slicing", &Family::ALL).unwrap_err();
        assert!(err.to_string().contains("'slicing'"), "{err}");
    }

    #[test]
    fn each_sweep_has_its_rows() {
        let base = FrameSettings::default();
        let res = ReportSweep::Resolution.rows(&base, &[]).unwrap();
        assert_eq!(res.len(), 3 * CULLING_METHODS.len());
        assert_eq!(res[1].series, "frag");
        assert_eq!(res[1].point, "res 512");
        assert_eq!(res[4].settings.shadow.resolution, 1024);
        let cascades = ReportSweep::Cascades.rows(&base, &[]).unwrap();
        assert_eq!(cascades.len(), 6);
        let spot = LightKind::Spot {
            direction: glam::Vec3::NEG_Y,
            inner_cone_rad: 0.2,
            outer_cone_rad: 0.4,
        };
        let maps = ReportSweep::Maps
            .rows(&base, &[LightKind::Point, spot, spot])
            .unwrap();
        // 1, 2 and 3 lights (the scene has three), each path.
        let points: Vec<&str> = maps.iter().map(|r| r.point.as_str()).collect();
        assert_eq!(points[0], "1 (6)");
        assert_eq!(points[3], "2 (7)");
        assert_eq!(points[6], "3 (8)");
        assert_eq!(maps.len(), 9);
        assert_eq!(maps[8].settings.layered.lights, 3);
    }
}
