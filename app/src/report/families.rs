//! The technique families a report runs, and the settings of each one's rows.

use render_core::frame::{FrameSettings, Method, ShadowSetup};
use render_core::shadow_view::{LayeredPath, VolumeClamp};

/// A group of rows compared with each other: their speed-ups are against the first row.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Family {
    Culling,
    Setups,
    Volumes,
    Lights,
}

/// One row to run: its label and its settings.
pub struct Setting {
    pub label: String,
    pub settings: FrameSettings,
}

impl Family {
    pub const ALL: [Self; 4] = [Self::Culling, Self::Setups, Self::Volumes, Self::Lights];

    pub fn name(self) -> &'static str {
        match self {
            Self::Culling => "culling",
            Self::Setups => "setups",
            Self::Volumes => "volumes",
            Self::Lights => "lights",
        }
    }

    pub fn named(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|f| f.name() == name)
    }

    /// Its section's title before the colon, what it compares after.
    pub fn description(self) -> &'static str {
        match self {
            Self::Culling => {
                "Caster culling: every method of Bittner et al. and DigitalRune on one shadow map \
                 of the sun, fitted to the view (the speed-ups are against `none`, which draws \
                 every caster)"
            }
            Self::Setups => {
                "Shadow setups: one map fitted to the view, LiSPSM, cascades, with the view's \
                 method (the speed-ups are against the single map)"
            }
            Self::Volumes => {
                "Shadow volumes: standard volumes, then culled and clamped by the visible \
                 receivers as Lloyd et al.'s CC shadow volumes (continuous, discrete, \
                 conservative, exact, by boxes; the speed-ups and the fill saved are against \
                 standard volumes)"
            }
            Self::Lights => {
                "Many lights: the scene's lights' maps rendered a pass per map, by multiview \
                 groups and by an instanced atlas (Rákos; the speed-ups are against a pass per \
                 map)"
            }
        }
    }

    /// The rows, from the view's settings.
    pub fn settings(self, base: &FrameSettings) -> Vec<Setting> {
        let base = *base;
        let with = |label: String, settings: FrameSettings| Setting { label, settings };
        match self {
            Self::Culling => Method::ALL
                .into_iter()
                .map(|method| {
                    with(
                        method.name().to_owned(),
                        FrameSettings {
                            setup: ShadowSetup::Single,
                            method,
                            ..base
                        },
                    )
                })
                .collect(),
            Self::Setups => [
                ShadowSetup::Single,
                ShadowSetup::Lispsm,
                ShadowSetup::Cascades,
                ShadowSetup::Virtual,
            ]
            .into_iter()
            .map(|setup| with(setup.name().to_owned(), FrameSettings { setup, ..base }))
            .collect(),
            Self::Volumes => {
                let volumes = |method, clamp| {
                    let mut s = FrameSettings {
                        setup: ShadowSetup::Volumes,
                        method,
                        ..base
                    };
                    s.volumes.clamp = clamp;
                    s
                };
                let standard = with("standard".into(), volumes(Method::None, VolumeClamp::None));
                let culled = with("culled".into(), volumes(Method::Vfc, VolumeClamp::None));
                let clamped = VolumeClamp::ALL
                    .into_iter()
                    .filter(|c| *c != VolumeClamp::None)
                    .map(|clamp| {
                        with(
                            format!("clamp {}", clamp.name()),
                            volumes(Method::Vfc, clamp),
                        )
                    });
                [standard, culled].into_iter().chain(clamped).collect()
            }
            Self::Lights => LayeredPath::ALL
                .into_iter()
                .map(|path| {
                    let mut s = FrameSettings {
                        setup: ShadowSetup::Lights,
                        method: Method::Vfc,
                        ..base
                    };
                    s.layered.path = path;
                    with(path.name().to_owned(), s)
                })
                .collect(),
        }
    }
}

impl Family {
    /// The views the section shows, each with the overlays that explain the family.
    pub fn pictures(self, base: &FrameSettings) -> Vec<Setting> {
        let base = *base;
        let mut settings = FrameSettings {
            measure: true,
            ..base
        };
        let with = |label: &str, settings: FrameSettings| Setting {
            label: label.to_owned(),
            settings,
        };
        match self {
            Self::Culling => {
                settings.setup = ShadowSetup::Single;
                settings.method = Method::Frag;
                settings.overlays.light_view = true;
                settings.overlays.casters = true;
                vec![with(
                    "frag: objects tinted by what culling did to them, and the light's view with \
                     the receiver mask and the culled casters striped",
                    settings,
                )]
            }
            Self::Setups => {
                settings.setup = ShadowSetup::Cascades;
                settings.overlays.cascades = true;
                let mut pages = FrameSettings {
                    setup: ShadowSetup::Virtual,
                    ..settings
                };
                pages.overlays.cascades = false;
                pages.overlays.light_view = true;
                vec![
                    with(
                        "cascades: each point tinted by the cascade that shades it",
                        settings,
                    ),
                    with(
                        "virtual maps: every clipmap level's pages, drawn this frame or cached",
                        pages,
                    ),
                ]
            }
            Self::Volumes => {
                settings.setup = ShadowSetup::Volumes;
                settings.overlays.fill = true;
                let standard = FrameSettings {
                    method: Method::None,
                    ..settings
                };
                settings.method = Method::Vfc;
                settings.volumes.clamp = VolumeClamp::Conservative;
                vec![
                    with(
                        "standard volumes: the fill heat map (fragments per pixel)",
                        standard,
                    ),
                    with(
                        "CC volumes, conservative clamping: the fill heat map",
                        settings,
                    ),
                ]
            }
            Self::Lights => {
                settings.setup = ShadowSetup::Lights;
                settings.method = Method::Vfc;
                settings.layered.path = LayeredPath::Atlas;
                settings.overlays.casters = true;
                vec![with(
                    "the scene's lights through their maps (atlas), objects tinted by whether a \
                     light's map drew them",
                    settings,
                )]
            }
        }
    }
}

/// `--families`: a comma list or `all`; many lights only where the scene has lights (`all`
/// leaves them out with a note, naming them is an error).
pub fn parse(list: &str, has_lights: bool) -> anyhow::Result<(Vec<Family>, Vec<String>)> {
    let mut notes = Vec::new();
    let families = if list.trim() == "all" {
        if !has_lights {
            notes.push(
                "the scene has no point or spot lights, so the many-lights family is left out"
                    .to_owned(),
            );
        }
        Family::ALL
            .into_iter()
            .filter(|f| has_lights || *f != Family::Lights)
            .collect()
    } else {
        let families = list
            .split(',')
            .map(|name| {
                Family::named(name.trim()).ok_or_else(|| {
                    anyhow::anyhow!(
                        "--families: '{}' is not a family (culling, setups, volumes, lights, or all)",
                        name.trim()
                    )
                })
            })
            .collect::<anyhow::Result<Vec<_>>>()?;
        if !has_lights && families.contains(&Family::Lights) {
            anyhow::bail!(
                "--families: 'lights' needs a scene with point or spot lights (builtin:hall, \
                 builtin:city-night, or a glTF with KHR_lights_punctual)"
            );
        }
        families
    };
    Ok((families, notes))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn families_parse_and_name_what_is_wrong() {
        let (all, notes) = parse("all", false).unwrap();
        assert_eq!(all, vec![Family::Culling, Family::Setups, Family::Volumes]);
        assert_eq!(notes.len(), 1);
        assert_eq!(parse("all", true).unwrap().0.len(), 4);
        assert_eq!(
            parse("volumes, culling", true).unwrap().0,
            vec![Family::Volumes, Family::Culling]
        );
        assert!(
            parse("cull", true)
                .unwrap_err()
                .to_string()
                .contains("'cull'")
        );
        assert!(
            parse("lights", false)
                .unwrap_err()
                .to_string()
                .contains("lights")
        );
    }

    #[test]
    fn each_family_has_its_rows() {
        let base = FrameSettings::default();
        assert_eq!(Family::Culling.settings(&base).len(), Method::ALL.len());
        let volumes = Family::Volumes.settings(&base);
        assert_eq!(volumes[0].label, "standard");
        assert_eq!(volumes[0].settings.method, Method::None);
        assert!(
            volumes
                .iter()
                .all(|s| s.settings.setup == ShadowSetup::Volumes)
        );
        assert_eq!(volumes.len(), 2 + VolumeClamp::ALL.len() - 1);
        let lights = Family::Lights.settings(&base);
        assert_eq!(lights[2].settings.layered.path, LayeredPath::Atlas);
    }
}
