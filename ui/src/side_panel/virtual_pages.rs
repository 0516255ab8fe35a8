//! The virtual maps' rows of the Shadows tab: the pool, the clipmap, resolution matching's
//! bias and the cache, and the pages of the newest frame that came back.

use render_core::frame::FrameReport;
use render_core::shadow_view::VirtualSettings;

use super::grid;
use crate::format::{length, thousands};

const POOL_HELP: &str = "Physical pages of 128 x 128 texels (64 KiB each) that hold the pages \
    visible pixels need. 1,024 pages are 64 MiB, the memory of four cascades of 2048. When \
    they run out, pixels read a coarser level and the refused pages are counted";
const LEVELS_HELP: &str = "Clipmap levels around the camera, each a square of 32 x 32 pages \
    whose texels are twice the last level's. From a point or spot light: mips per face of its \
    cube, or of the spot's cone, down to one page (8, the most: from 16,384 texels square; 6: \
    from 4096)";
const TEXEL_HELP: &str = "The finest level's texel. Each pixel reads the finest level whose \
    texel is no larger than its own footprint (resolution matching)";
const BIAS_HELP: &str = "Octaves added to the level resolution matching picks: above 0 \
    coarser (fewer pages), below 0 finer (more pages), as Unreal's \
    ResolutionLodBiasDirectional";
const CACHE_HELP: &str = "Pages stay drawn across frames until something moves through them \
    or the light moves; off draws every needed page each frame";
const MASK_HELP: &str = "Casters are culled against the blocks of 16 x 16 texels that \
    visible pixels read, not whole pages (Unreal 5.6's receiver mask): every caster with one \
    layer per page, the movable casters with static casters apart. A page it leaves partial is \
    drawn again next frame";
const APART_HELP: &str = "Each page keeps static casters' depths apart from movable ones', so a \
    moving object draws only the movable casters of the pages it touches again (Unreal's \
    static separation), and only once pixels read a block of 16 x 16 texels it covered; the \
    pool takes twice the memory";
const OCCLUSION_HELP: &str = "With static casters apart: a movable caster wholly behind a cached     page's static casters, as the light sees them (block by block of 16 x 16 texels), neither     makes the page's movable layer stale when it moves nor is drawn into it. A car in a     building's shadow redraws nothing. Exact: no texel's nearest depth changes";

/// The rows (inside the tab's grid).
pub fn rows(ui: &mut egui::Ui, settings: &mut VirtualSettings, report: Option<&FrameReport>) {
    grid::labelled(ui, "Pool", POOL_HELP, |ui| {
        ui.add(
            egui::DragValue::new(&mut settings.pages)
                .range(VirtualSettings::MIN_PAGES..=VirtualSettings::MAX_PAGES)
                .suffix(" pages"),
        )
    });
    grid::row(ui, "Pool memory", format!("{:.0} MiB", settings.pool_mib()));
    grid::labelled(ui, "Levels", LEVELS_HELP, |ui| {
        ui.add(egui::DragValue::new(&mut settings.levels).range(1..=VirtualSettings::MAX_LEVELS))
    });
    grid::labelled(ui, "Finest texel", TEXEL_HELP, |ui| {
        ui.add(
            egui::DragValue::new(&mut settings.finest_texel_m)
                .range(0.0001..=1.0)
                .speed(0.0005)
                .custom_formatter(|v, _| length(v as f32)),
        )
    });
    grid::labelled(ui, "Level bias", BIAS_HELP, |ui| {
        ui.add(egui::Slider::new(&mut settings.lod_bias, -2.0..=2.0).suffix(" oct"))
    });
    grid::labelled(ui, "Cache", CACHE_HELP, |ui| {
        ui.checkbox(&mut settings.cache, "keep pages")
    });
    grid::labelled(ui, "Static apart", APART_HELP, |ui| {
        ui.checkbox(
            &mut settings.separate_static,
            "static casters in a layer of their own",
        )
    });
    grid::labelled(ui, "Static occlusion", OCCLUSION_HELP, |ui| {
        ui.add_enabled(
            settings.separate_static,
            egui::Checkbox::new(
                &mut settings.static_occlusion,
                "movable casters behind static ones skipped",
            ),
        )
    });
    grid::labelled(ui, "Receiver mask", MASK_HELP, |ui| {
        ui.checkbox(
            &mut settings.receiver_mask,
            "cull casters per 16-texel block",
        )
    });
    let Some(p) = report.and_then(|r| r.virtual_pages) else {
        return;
    };
    grid::row(
        ui,
        "Pages",
        format!(
            "{} marked, {} resident, {} drawn",
            thousands(p.pages_marked.into()),
            thousands(p.pages_resident.into()),
            thousands(p.pages_rendered.into())
        ),
    );
    if p.separate_static {
        grid::row(
            ui,
            "Refreshed",
            format!(
                "{} pages' movable casters alone drawn",
                thousands(p.pages_refreshed.into())
            ),
        );
    }
    if p.static_occlusion {
        grid::row(
            ui,
            "Occluded",
            format!(
                "{} pages kept fresh behind static casters, {} draws left out",
                thousands(p.moved_pages_occluded.into()),
                thousands(p.caster_pages_occluded.into())
            ),
        );
    }
    grid::row(
        ui,
        "Cache hits",
        p.cache_hit_rate.map_or_else(
            || "no page marked".to_owned(),
            |rate| format!("{:.0}% of the marked pages were kept", 100.0 * rate),
        ),
    );
    let refused = if p.pages_refused > 0 {
        format!("{} refused (pool full)", thousands(p.pages_refused.into()))
    } else {
        "none refused".to_owned()
    };
    grid::row(
        ui,
        "Pool",
        format!("{refused}, {} evicted", p.pages_evicted),
    );
    grid::row(
        ui,
        "Occupancy",
        format!(
            "{:.0}% of {} pages",
            100.0 * f64::from(p.pages_resident) / f64::from(p.pool_pages.max(1)),
            p.pool_pages
        ),
    );
    let casters = format!("{} (caster, page) draws", thousands(p.caster_pages.into()));
    let masked = if p.receiver_mask {
        format!(
            ", {} left out by the receiver mask",
            thousands(p.caster_pages_masked.into())
        )
    } else {
        String::new()
    };
    grid::row(ui, "Casters", format!("{casters}{masked}"));
}
