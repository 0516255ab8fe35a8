//! The virtual maps' per-page oracle (`virtual_maps/oracle.rs`): of the (caster, page) pairs a
//! frame draws, those holding a texel that a visible pixel's tap reads shadowed. A box over a
//! ground: the oracle holds the box, never the ground, in exactly the pages the box's shadow
//! is read from (a CPU reference of the pages each shadowed pixel reads); every exact variant
//! of the cull (the receiver mask, static casters apart) has the same oracle; and it is
//! measured only where the frame drew every page it reads.

use render_core::scene::Sun;
use render_core::shadow_view::VirtualSettings;
use render_core::virtual_maps::DrawnPair;
use shadowlab_tests::virtual_pages::{
    Frame, Frames, Marking, SIZE, box_scene_normal, camera, scene, settings,
};
use shadowlab_tests::{gpu, world_position};

const LEVEL_ENTRIES: u32 = 1024;

fn uncached() -> VirtualSettings {
    VirtualSettings {
        cache: false,
        ..VirtualSettings::default()
    }
}

/// A frame of the box scene and its pairs.
fn frame_and_pairs(v: VirtualSettings) -> (Frame, Vec<DrawnPair>) {
    let scene = scene(Sun::default());
    let mut frames = Frames::new(&scene);
    let frame = frames.frame(&scene, &camera(), &settings(v));
    let pairs = frames.renderer.virtual_pairs(gpu()).expect("reads back");
    (frame, pairs)
}

/// The oracle's (caster, entry) pairs, sorted.
fn oracle_of(pairs: &[DrawnPair]) -> Vec<(u32, u32)> {
    let mut out: Vec<(u32, u32)> = pairs
        .iter()
        .filter(|p| p.oracle)
        .map(|p| (p.instance, p.entry))
        .collect();
    out.sort_unstable();
    out
}

#[test]
fn the_oracle_holds_the_box_in_exactly_the_pages_its_shadow_is_read_from() {
    let v = uncached();
    let (frame, pairs) = frame_and_pairs(v);
    let scene = scene(Sun::default());
    assert_eq!(pairs.len() as u32, frame.pages.caster_pages);
    let oracle = oracle_of(&pairs);
    // Only the box shadows what the camera sees; the ground is drawn into every page, needed
    // in none.
    assert!(!oracle.is_empty());
    assert!(
        oracle.iter().all(|&(instance, _)| instance == 1),
        "{oracle:?}"
    );
    assert!(pairs.iter().any(|p| p.instance == 0));
    // The counts: in total, per level, and the tightness they make.
    let report = &frame.report;
    assert_eq!(report.counts.casters_oracle, Some(oracle.len() as u32));
    for (level, view) in report.views.iter().enumerate() {
        let in_level = oracle
            .iter()
            .filter(|(_, e)| e / LEVEL_ENTRIES == level as u32)
            .count() as u32;
        assert_eq!(view.casters_oracle, Some(in_level), "{}", view.name);
    }
    let tightness = report.tightness().expect("an oracle");
    assert!((tightness - pairs.len() as f64 / oracle.len() as f64).abs() < 1e-12);
    assert!(tightness > 1.0);

    // The CPU's pages: those the taps of pixels in shadow read. Sure where a pixel and its
    // neighbours are wholly shadowed and its pages certain; possible wherever a pixel or a
    // neighbour has any tap shadowed (marking reads the surface a texel apart from shading).
    let camera = camera();
    let marking = Marking::new(&camera, &frame.views, v);
    let factor = |x: i64, y: i64| {
        let (x, y) = (
            x.clamp(0, i64::from(SIZE.0) - 1),
            y.clamp(0, i64::from(SIZE.1) - 1),
        );
        frame.capture.shadow[(y * i64::from(SIZE.0) + x) as usize]
    };
    let (mut sure, mut possible) = (Vec::new(), Vec::new());
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let Some(p) = world_position(&frame.capture, &camera, x, y) else {
                continue;
            };
            let id = frame.capture.ids[(y * SIZE.0 + x) as usize];
            let marks = marking.marks(p, box_scene_normal(&scene, id, p));
            let around: Vec<u8> = (-1..=1)
                .flat_map(|dy| (-1..=1).map(move |dx| (dx, dy)))
                .map(|(dx, dy)| factor(i64::from(x) + dx, i64::from(y) + dy))
                .collect();
            if around.iter().any(|&f| f < 255) {
                possible.extend(marks.entries.iter().map(|&e| e as u32));
            }
            if marks.certain && around.iter().all(|&f| f == 0) {
                sure.extend(marks.entries.iter().map(|&e| e as u32));
            }
        }
    }
    for set in [&mut sure, &mut possible] {
        set.sort_unstable();
        set.dedup();
    }
    let gpu_pages: Vec<u32> = oracle.iter().map(|&(_, e)| e).collect();
    assert!(!sure.is_empty());
    let missing: Vec<_> = sure.iter().filter(|e| !gpu_pages.contains(e)).collect();
    assert!(missing.is_empty(), "the oracle left out {missing:?}");
    let extra: Vec<_> = gpu_pages.iter().filter(|e| !possible.contains(e)).collect();
    assert!(extra.is_empty(), "no shadowed pixel reads {extra:?}");
}

#[test]
fn every_exact_cull_has_the_same_oracle_measured_only_where_every_page_is_drawn() {
    let (plain, plain_pairs) = frame_and_pairs(uncached());
    let expected = oracle_of(&plain_pairs);
    assert!(!expected.is_empty());
    // The receiver mask draws fewer pairs, the same needed ones: a tighter cull.
    let (masked, masked_pairs) = frame_and_pairs(VirtualSettings {
        receiver_mask: true,
        ..uncached()
    });
    assert_eq!(oracle_of(&masked_pairs), expected);
    assert!(masked_pairs.len() < plain_pairs.len());
    let tightness = |f: &Frame| f.report.tightness().expect("an oracle");
    assert!(tightness(&masked) < tightness(&plain));
    // Static casters apart: the moving box in the movable layer, the same oracle.
    let (_, apart_pairs) = frame_and_pairs(VirtualSettings {
        separate_static: true,
        ..uncached()
    });
    assert_eq!(oracle_of(&apart_pairs), expected);
    assert!(
        apart_pairs
            .iter()
            .all(|p| p.movable_layer == (p.instance == 1))
    );

    // With the cache, the first frame draws every page it reads: the same oracle. The
    // second draws none, and measures none.
    let scene = scene(Sun::default());
    let mut frames = Frames::new(&scene);
    let cached = settings(VirtualSettings::default());
    let first = frames.frame(&scene, &camera(), &cached);
    assert!(first.pages.all_invalidated);
    let first_pairs = frames.renderer.virtual_pairs(gpu()).expect("reads back");
    assert_eq!(oracle_of(&first_pairs), expected);
    assert_eq!(
        first.report.counts.casters_oracle,
        Some(expected.len() as u32)
    );
    let second = frames.frame(&scene, &camera(), &cached);
    assert_eq!(second.pages.pages_rendered, 0);
    assert_eq!(second.report.counts.casters_oracle, None);
    assert!(
        second
            .report
            .views
            .iter()
            .all(|v| v.casters_oracle.is_none())
    );
}
