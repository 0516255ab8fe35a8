//! The settings `bench --sweep` runs (and `report`'s sweeps): a label and the frame settings
//! for each value of the swept parameter, the other settings the view's.

use render_core::cascades::{MAX_CASCADES, SplitScheme};
use render_core::frame::{FrameSettings, ShadowSettings, ShadowSetup};
use render_core::scene::Sun;
use render_core::volumes::VolumeClamp;

use crate::cli::{BenchArgs, Sweep};

/// The values the sweeps run over.
#[derive(Clone, Debug)]
pub(crate) struct SweepValues {
    pub resolutions: Vec<u32>,
    /// Sun elevations, degrees (the azimuth stays the view's).
    pub elevations: Vec<f32>,
    pub cascade_counts: Vec<u32>,
    pub lambdas: Vec<f32>,
}

impl From<&BenchArgs> for SweepValues {
    fn from(args: &BenchArgs) -> Self {
        Self {
            resolutions: args.resolutions.clone(),
            elevations: args.elevations.clone(),
            cascade_counts: args.cascade_counts.clone(),
            lambdas: args.lambdas.clone(),
        }
    }
}

/// The shadow volumes' slice counts of `--sweep slices` (Lloyd's Figure 9).
pub(crate) const SLICES: [u32; 6] = [1, 2, 4, 8, 16, 32];

/// The label of `--sweep slices`' first setting: standard volumes, unclamped.
pub(crate) const STANDARD_VOLUMES: &str = "standard";

/// The settings of `sweep` over `values`, each with its label (`res 2048`, `sun 30°`...).
/// Many lights' and the object counts' sweeps have rows of their own: they give the view's
/// settings alone.
pub(crate) fn settings(
    sweep: Sweep,
    base: &FrameSettings,
    values: &SweepValues,
) -> anyhow::Result<Vec<(String, FrameSettings)>> {
    let base = *base;
    values.check()?;
    let with_setup = |setup| FrameSettings { setup, ..base };
    Ok(match sweep {
        Sweep::Maps | Sweep::Objects => vec![(String::new(), base)],
        Sweep::Resolution => values
            .resolutions
            .iter()
            .map(|&res| {
                let mut s = base;
                s.shadow.resolution = res;
                (format!("res {res}"), s)
            })
            .collect(),
        Sweep::Elevation => {
            let (azimuth, _) = base.sun.azimuth_elevation_deg();
            values
                .elevations
                .iter()
                .map(|&elevation| {
                    let sun = Sun::from_azimuth_elevation_deg(azimuth, elevation);
                    (format!("sun {elevation}°"), FrameSettings { sun, ..base })
                })
                .collect()
        }
        Sweep::Cascades => [
            ("single".to_owned(), with_setup(ShadowSetup::Single)),
            ("lispsm".to_owned(), with_setup(ShadowSetup::Lispsm)),
        ]
        .into_iter()
        .chain(values.cascade_counts.iter().map(|&count| {
            let mut s = with_setup(ShadowSetup::Cascades);
            s.cascades.count = count;
            let plural = if count == 1 { "" } else { "s" };
            (format!("{count} cascade{plural}"), s)
        }))
        .collect(),
        Sweep::Clamp => VolumeClamp::ALL
            .into_iter()
            .map(|clamp| {
                let mut s = with_setup(ShadowSetup::Volumes);
                s.volumes.clamp = clamp;
                (format!("clamp {}", clamp.name()), s)
            })
            .collect(),
        Sweep::Slices => {
            // Standard volumes first: the rows after are measured against them.
            let mut standard = with_setup(ShadowSetup::Volumes);
            standard.volumes.clamp = VolumeClamp::None;
            let sliced = SLICES.into_iter().map(|slices| {
                let mut s = with_setup(ShadowSetup::Volumes);
                if !matches!(s.volumes.clamp, VolumeClamp::Discrete) {
                    s.volumes.clamp = VolumeClamp::Conservative;
                }
                s.volumes.slices = slices;
                let plural = if slices == 1 { "" } else { "s" };
                (format!("{slices} slice{plural}"), s)
            });
            std::iter::once((STANDARD_VOLUMES.to_owned(), standard))
                .chain(sliced)
                .collect()
        }
        Sweep::Virtual => {
            let mut single = with_setup(ShadowSetup::Single);
            single.shadow.resolution = 8192;
            let mut cascades = with_setup(ShadowSetup::Cascades);
            cascades.cascades.count = 4;
            cascades.shadow.resolution = 2048;
            let virtual_maps = with_setup(ShadowSetup::Virtual);
            let mut uncached = virtual_maps;
            uncached.virtual_maps.cache = false;
            // Static casters apart, in the same memory: half the pages, two layers each.
            let mut apart = virtual_maps;
            apart.virtual_maps.separate_static = true;
            apart.virtual_maps.pages = virtual_maps.virtual_maps.pages / 2;
            // The receiver mask where it culls: with the cache off, and on the movable layer.
            let mut masked = uncached;
            masked.virtual_maps.receiver_mask = true;
            let mut apart_masked = apart;
            apart_masked.virtual_maps.receiver_mask = true;
            // Static occlusion's share: every moved box refreshes the pages it touches.
            let mut unoccluded = apart;
            unoccluded.virtual_maps.static_occlusion = false;
            // A point light's shadows: shadow volumes, exact, where the maps would have none.
            let against = if base.point_light.is_some() {
                vec![(
                    "shadow volumes".to_owned(),
                    with_setup(ShadowSetup::Volumes),
                )]
            } else {
                vec![
                    ("single 8192".to_owned(), single),
                    ("4 cascades 2048".to_owned(), cascades),
                ]
            };
            let mut rows = against;
            rows.extend([
                ("virtual".to_owned(), virtual_maps),
                ("virtual / cache off".to_owned(), uncached),
                ("virtual / cache off + receiver mask".to_owned(), masked),
                ("virtual / static apart".to_owned(), apart),
                (
                    "virtual / static apart / occlusion off".to_owned(),
                    unoccluded,
                ),
                (
                    "virtual / static apart + receiver mask".to_owned(),
                    apart_masked,
                ),
            ]);
            rows
        }
        Sweep::Setups => ShadowSetup::ALL
            .into_iter()
            .map(|setup| (setup.name().to_owned(), with_setup(setup)))
            .collect(),
        Sweep::Splits => SplitScheme::ALL
            .into_iter()
            .filter(|s| *s != SplitScheme::Manual)
            .map(|scheme| {
                let mut s = with_setup(ShadowSetup::Cascades);
                s.cascades.splits.scheme = scheme;
                (scheme.name().to_owned(), s)
            })
            .collect(),
        Sweep::Lambda => values
            .lambdas
            .iter()
            .map(|&lambda| {
                let mut s = with_setup(ShadowSetup::Cascades);
                s.cascades.splits.scheme = SplitScheme::Practical;
                s.cascades.splits.lambda = lambda;
                (format!("lambda {lambda}"), s)
            })
            .collect(),
    })
}

impl SweepValues {
    /// Each value within its setting's range, or an error naming the flag and the value.
    fn check(&self) -> anyhow::Result<()> {
        let limits = ShadowSettings::MIN_RESOLUTION..=ShadowSettings::MAX_RESOLUTION;
        if let Some(res) = self.resolutions.iter().find(|r| !limits.contains(r)) {
            anyhow::bail!(
                "--resolutions: {res} is outside {} to {}",
                limits.start(),
                limits.end()
            );
        }
        if let Some(el) = self
            .elevations
            .iter()
            .find(|e| !(e.is_finite() && **e > 0.0 && **e <= 90.0))
        {
            anyhow::bail!(
                "--elevations: {el} is not an elevation above the horizon (0 < degrees <= 90)"
            );
        }
        if let Some(n) = self
            .cascade_counts
            .iter()
            .find(|n| !(1..=MAX_CASCADES).contains(n))
        {
            anyhow::bail!("--cascade-counts: {n} is outside 1 to {MAX_CASCADES}");
        }
        if let Some(l) = self.lambdas.iter().find(|l| !(0.0..=1.0).contains(*l)) {
            anyhow::bail!("--lambdas: {l} is outside 0 to 1");
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn values() -> SweepValues {
        SweepValues {
            resolutions: vec![512, 1024],
            elevations: vec![10.0, 45.0],
            cascade_counts: vec![2, 4],
            lambdas: vec![0.5],
        }
    }

    #[test]
    fn each_sweep_sets_what_it_varies() {
        let base = FrameSettings::default();
        let res = settings(Sweep::Resolution, &base, &values()).unwrap();
        assert_eq!(res[1].0, "res 1024");
        assert_eq!(res[1].1.shadow.resolution, 1024);
        let sun = settings(Sweep::Elevation, &base, &values()).unwrap();
        let (_, elevation) = sun[1].1.sun.azimuth_elevation_deg();
        assert!((elevation - 45.0).abs() < 1e-3, "{elevation}");
        let cascades = settings(Sweep::Cascades, &base, &values()).unwrap();
        let labels: Vec<&str> = cascades.iter().map(|(l, _)| l.as_str()).collect();
        assert_eq!(labels, ["single", "lispsm", "2 cascades", "4 cascades"]);
        assert_eq!(cascades[3].1.cascades.count, 4);
        let slices = settings(Sweep::Slices, &base, &values()).unwrap();
        // The virtual maps against the maps of the sun, or a point light's shadow volumes.
        let names = |base: &FrameSettings| {
            let rows = settings(Sweep::Virtual, base, &values()).unwrap();
            rows.iter().map(|(_, s)| s.setup).collect::<Vec<_>>()[..2].to_vec()
        };
        assert_eq!(names(&base), [ShadowSetup::Single, ShadowSetup::Cascades]);
        let point = FrameSettings {
            point_light: Some(render_core::scene::PointShadow::omni(glam::Vec3::Y, 1.0)),
            ..base
        };
        assert_eq!(names(&point), [ShadowSetup::Volumes, ShadowSetup::Virtual]);
        assert_eq!(slices.len(), 1 + SLICES.len());
        assert_eq!(slices[0].0, STANDARD_VOLUMES);
        assert_eq!(slices[0].1.volumes.clamp, VolumeClamp::None);
        assert_eq!(slices[6].0, "32 slices");
        assert_eq!(slices[6].1.volumes.slices, 32);
        assert_eq!(slices[6].1.volumes.clamp, VolumeClamp::Conservative);
    }

    #[test]
    fn a_value_out_of_range_is_named() {
        let base = FrameSettings::default();
        let wrong = SweepValues {
            cascade_counts: vec![99],
            ..values()
        };
        let err = settings(Sweep::Cascades, &base, &wrong).unwrap_err();
        assert!(err.to_string().contains("--cascade-counts: 99"), "{err}");
        let wrong = SweepValues {
            elevations: vec![0.0],
            ..values()
        };
        assert!(settings(Sweep::Elevation, &base, &wrong).is_err());
    }
}
