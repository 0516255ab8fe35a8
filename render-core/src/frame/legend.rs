//! The legend of the overlays a frame shows, for the view and for screenshots: each overlay's
//! colours from `crate::palette` and what they mean.

use crate::culling::Method;
use crate::culling::codes::method_bits;
use crate::palette::{
    CULLED_LIGHT_FRUSTUM, CULLED_LIGHT_OCCLUSION, CULLED_MASK, EXCLUDED, EXTRA_SHADOW, MAP_EMPTY,
    MAP_FAR, MAP_NEAR, MASK_BOX, MASK_FRAGMENT, MASK_GEOMETRY, MISSING_SHADOW, RENDERED, Swatch,
    VIEWS,
};

use super::FrameSettings;

/// The cascade tint's lines, nearest first.
const VIEW_LABELS: [&str; 8] = [
    "cascade 0 (nearest)",
    "cascade 1",
    "cascade 2",
    "cascade 3",
    "cascade 4",
    "cascade 5",
    "cascade 6",
    "cascade 7",
];

/// One line of a legend: a colour (striped when the picture shows it as stripes) and what it
/// means.
#[derive(Clone, Debug, PartialEq)]
pub struct LegendEntry {
    pub rgb: [f32; 3],
    pub striped: bool,
    pub label: &'static str,
}

/// The legend of one overlay.
#[derive(Clone, Debug, PartialEq)]
pub struct LegendGroup {
    pub title: &'static str,
    pub entries: Vec<LegendEntry>,
}

fn entry(swatch: Swatch, label: &'static str) -> LegendEntry {
    LegendEntry {
        rgb: swatch.rgb,
        striped: false,
        label,
    }
}

/// What caster outcome colours mean, for the tint and (striped) for the inset.
fn outcomes(striped: bool) -> Vec<LegendEntry> {
    [
        (RENDERED, "rendered into the map"),
        (CULLED_LIGHT_FRUSTUM, "culled: light frustum"),
        (CULLED_LIGHT_OCCLUSION, "culled: light occlusion"),
        (CULLED_MASK, "culled: receiver mask, footprint or volume"),
        (EXCLUDED, "excluded on request"),
    ]
    .into_iter()
    .filter(|(s, _)| !striped || *s != RENDERED)
    .map(|(swatch, label)| LegendEntry {
        striped,
        ..entry(swatch, label)
    })
    .collect()
}

/// The legend of every overlay `settings` turn on, in the order the picture draws them; empty
/// when no overlay is on. The light view lists the mask the method draws.
pub fn legend(settings: &FrameSettings) -> Vec<LegendGroup> {
    let overlays = settings.overlays;
    let mut groups = Vec::new();
    if overlays.casters {
        groups.push(LegendGroup {
            title: "Casters tint",
            entries: outcomes(false),
        });
    }
    // Shadow volumes have no views to tint by.
    if overlays.cascades && settings.setup != super::ShadowSetup::Volumes {
        let count = if settings.cascaded_sun() {
            settings.cascades.count.clamp(1, VIEWS.len() as u32)
        } else {
            1
        };
        groups.push(LegendGroup {
            title: "Cascade tint",
            entries: VIEWS
                .iter()
                .zip(VIEW_LABELS)
                .take(count as usize)
                .map(|(swatch, label)| entry(*swatch, label))
                .collect(),
        });
    }
    if overlays.error && settings.measure {
        groups.push(LegendGroup {
            title: "Error against the reference",
            entries: vec![
                entry(MISSING_SHADOW, "shadow missing"),
                entry(EXTRA_SHADOW, "shadow where there is none"),
            ],
        });
    }
    if overlays.fill && settings.setup == super::ShadowSetup::Volumes {
        groups.push(LegendGroup {
            title: "Shadow-volume fill",
            entries: vec![
                entry(crate::palette::FILL_LOW, "1 fragment on the pixel"),
                entry(crate::palette::FILL_HIGH, "1,024 and more (log scale)"),
            ],
        });
    }
    if overlays.volumes && settings.setup == super::ShadowSetup::Volumes {
        groups.push(LegendGroup {
            title: "Shadow volumes",
            entries: vec![entry(
                crate::palette::VOLUME,
                "volume faces in front of the surface (brighter: more layers)",
            )],
        });
    }
    if overlays.light_view && settings.setup == super::ShadowSetup::Virtual {
        groups.push(LegendGroup {
            title: match settings.point_light {
                Some(light) if crate::shadow_view::spot_chain(&light).is_some() => {
                    "Pages of the spot's mips, finest first (top left)"
                }
                Some(_) => {
                    "Pages of each cube face (a row each: +X, -X, +Y, -Y, +Z, -Z), finest mip first"
                }
                None => "Pages of each level, finest first (top left)",
            },
            entries: [
                Some(entry(crate::palette::PAGE_DRAWN, "drawn this frame")),
                settings.virtual_maps.separate_static.then(|| {
                    entry(
                        crate::palette::PAGE_REFRESHED,
                        "movable casters drawn again, static kept",
                    )
                }),
                Some(entry(
                    crate::palette::PAGE_CACHED,
                    "cached, read this frame",
                )),
                Some(entry(crate::palette::PAGE_IDLE, "cached, not read")),
                Some(entry(
                    crate::palette::PAGE_REFUSED,
                    "refused: the pool is full",
                )),
                Some(entry(MAP_EMPTY, "no page")),
            ]
            .into_iter()
            .flatten()
            .collect(),
        });
    } else if overlays.light_view {
        let bits = settings.method.gpu_bits().unwrap_or(0);
        let mut entries = vec![
            entry(MAP_NEAR, "map: near the light"),
            entry(MAP_FAR, "map: far from the light"),
            entry(MAP_EMPTY, "map: no caster"),
        ];
        if bits & method_bits::RASTER_MASK != 0 {
            entries.push(entry(MASK_GEOMETRY, "mask: receiver geometry"));
            entries.push(entry(MASK_BOX, "mask: receiver box"));
        }
        if bits & method_bits::FRAG != 0 {
            entries.push(entry(MASK_FRAGMENT, "mask: visible receiver depths"));
        }
        if settings.measure || settings.method == Method::Oracle {
            if overlays.casters {
                entries.push(LegendEntry {
                    striped: true,
                    ..entry(CULLED_MASK, "stripes: culled casters, coloured as the tint")
                });
            } else {
                entries.extend(outcomes(true));
            }
        }
        groups.push(LegendGroup {
            title: "Light view (top left)",
            entries,
        });
    }
    groups
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::Overlays;

    #[test]
    fn the_legend_follows_the_overlays_and_the_method() {
        let mut settings = FrameSettings::default();
        assert!(legend(&settings).is_empty());

        settings.overlays = Overlays {
            light_view: true,
            error: true,
            casters: true,
            cascades: false,
            fill: false,
            volumes: false,
            inset_view: 0,
        };
        settings.method = Method::Frag;
        let titles: Vec<_> = legend(&settings).iter().map(|g| g.title).collect();
        // The error map needs measuring.
        assert_eq!(titles, ["Casters tint", "Light view (top left)"]);
        let light = legend(&settings).pop().expect("light view");
        let labels: Vec<_> = light.entries.iter().map(|e| e.label).collect();
        assert!(labels.contains(&"mask: visible receiver depths"));
        assert!(
            !labels.contains(&"mask: receiver box"),
            "FRAG draws no boxes"
        );
        assert!(
            light.entries.iter().all(|e| !e.striped),
            "no ids, no stripes"
        );

        settings.measure = true;
        settings.method = Method::Bvol;
        let groups = legend(&settings);
        assert_eq!(groups[1].entries[0].label, "shadow missing");
        assert!(
            groups[1].entries[0].rgb == MISSING_SHADOW.rgb,
            "the heat map's colour"
        );
        let light = &groups[2];
        assert!(
            light
                .entries
                .iter()
                .any(|e| e.label == "mask: receiver box")
        );
        let stripes = light.entries.iter().filter(|e| e.striped).count();
        assert_eq!(
            stripes, 1,
            "the tint's legend explains the stripes' colours"
        );
        settings.overlays.casters = false;
        let light = legend(&settings).pop().expect("light view");
        let stripes = light.entries.iter().filter(|e| e.striped).count();
        assert_eq!(stripes, 4, "every culled outcome, not rendered");

        // The cascade tint lists as many colours as there are cascades.
        settings.overlays = Overlays {
            cascades: true,
            ..Overlays::default()
        };
        settings.setup = super::super::ShadowSetup::Cascades;
        settings.cascades.count = 3;
        let groups = legend(&settings);
        assert_eq!(groups[0].title, "Cascade tint");
        let labels: Vec<_> = groups[0].entries.iter().map(|e| e.label).collect();
        assert_eq!(labels, ["cascade 0 (nearest)", "cascade 1", "cascade 2"]);
        let [r, g, b] = groups[0].entries[2].rgb;
        assert!((r, g, b) == (VIEWS[2].rgb[0], VIEWS[2].rgb[1], VIEWS[2].rgb[2]));
    }

    #[test]
    fn the_virtual_maps_light_view_is_their_pages() {
        let mut settings = FrameSettings {
            setup: crate::frame::ShadowSetup::Virtual,
            ..FrameSettings::default()
        };
        settings.overlays.light_view = true;
        let groups = legend(&settings);
        assert_eq!(groups.len(), 1);
        let labels: Vec<_> = groups[0].entries.iter().map(|e| e.label).collect();
        assert!(labels.contains(&"drawn this frame"), "{labels:?}");
        assert!(labels.contains(&"refused: the pool is full"), "{labels:?}");
        assert_eq!(groups[0].entries[0].label, "drawn this frame");
    }
}
