//! The virtual maps' receiver mask (`--receiver-mask on`, Unreal 5.6's): each page keeps a bit
//! per block of 16 x 16 texels that visible pixels' taps read, exactly the blocks a CPU
//! reference finds; a caster is drawn into a page only where its bounds cover such a block;
//! the picture is the one without the mask; and a page the mask left partial is drawn again
//! the next frame (whole, or its movable layer where static casters are apart).

use glam::Vec3;
use render_core::scene::{Scene, Sun};
use render_core::shadow_view::{LEVEL_PAGES, PAGE_TEXELS, ShadowView, VirtualSettings};
use shadowlab_tests::gpu;
use shadowlab_tests::virtual_pages::{
    Frame, Frames, MARKED, Marking, REFRESHED, RENDERED, SIZE, box_scene_normal, camera,
    entries_with, entry, level_texel, scene, settings,
};

/// A page the receiver mask left a caster out of (`virtual_maps/pages.wgsl`).
const PARTIAL: u32 = 128;
/// A page released at the next frame's start.
const INVALID: u32 = 16;
const BLOCK: i64 = 16;

/// A block of a page: its entry and its bit (row by row, 8 x 8).
type Block = (usize, u32);

fn block_of(views: &[ShadowView], level: usize, x: i64, y: i64) -> Block {
    let page = i64::from(PAGE_TEXELS);
    let e = entry(views, level, [x.div_euclid(page), y.div_euclid(page)]);
    let (bx, by) = (x.rem_euclid(page) / BLOCK, y.rem_euclid(page) / BLOCK);
    (e, (by * 8 + bx) as u32)
}

fn mask_has(masks: &[[u32; 2]], (e, bit): Block) -> bool {
    masks[e][(bit / 32) as usize] & (1 << (bit % 32)) != 0
}

/// The blocks the CPU is sure marking sets (those of the taps widened by a texel, in the pages
/// the taps read), and those it may set (a texel more where the CPU cannot be sure of the
/// first tap).
fn cpu_blocks(scene: &Scene, frame: &Frame, v: VirtualSettings) -> (Vec<Block>, Vec<Block>) {
    let camera = camera();
    let marking = Marking::new(&camera, &frame.views, v);
    let (mut sure, mut possible) = (Vec::new(), Vec::new());
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let id = frame.capture.ids[(y * SIZE.0 + x) as usize];
            let Some(p) = shadowlab_tests::world_position(&frame.capture, &camera, x, y) else {
                continue;
            };
            let marks = marking.marks(p, box_scene_normal(scene, id, p));
            // The taps widened by a texel (as marking widens them) within the pages the taps
            // read, and one more where the CPU cannot be sure of the first tap.
            let reach = 1 + i64::from(!marks.texels_certain);
            for &(level, tx, ty) in &marks.texels {
                for dy in -reach..=reach {
                    for dx in -reach..=reach {
                        let block = block_of(&frame.views, level, tx + dx, ty + dy);
                        if !marks.entries.contains(&block.0) {
                            continue;
                        }
                        if marks.texels_certain && dx.abs() <= 1 && dy.abs() <= 1 {
                            sure.push(block);
                        }
                        possible.push(block);
                    }
                }
            }
        }
    }
    for set in [&mut sure, &mut possible] {
        set.sort_unstable();
        set.dedup();
    }
    (sure, possible)
}

/// The (caster, page) pairs the cull should draw with the mask `masks`: each caster into each
/// drawn page of its bounds (widened by a texel) where it covers a block pixels read.
fn expected_pairs(scene: &Scene, frame: &Frame, masks: &[[u32; 2]]) -> u32 {
    let side = i64::from(LEVEL_PAGES);
    let page_texels = i64::from(PAGE_TEXELS);
    let mut pairs = 0;
    for instance in &scene.instances {
        let (lo, hi) = (instance.aabb_in_world.min, instance.aabb_in_world.max);
        for (level, view) in frame.views.iter().enumerate() {
            let (mut t_lo, mut t_hi) = ([f64::MAX; 2], [f64::MIN; 2]);
            for i in 0..8 {
                let corner = Vec3::new(
                    if i & 1 == 0 { lo.x } else { hi.x },
                    if i & 2 == 0 { lo.y } else { hi.y },
                    if i & 4 == 0 { lo.z } else { hi.z },
                );
                let t = level_texel(view, corner);
                for a in 0..2 {
                    t_lo[a] = t_lo[a].min(t[a]);
                    t_hi[a] = t_hi[a].max(t[a]);
                }
            }
            let first = t_lo.map(|t| (t - 1.0).floor() as i64);
            let last = t_hi.map(|t| (t + 1.0).floor() as i64);
            let page = |t: i64| t.div_euclid(page_texels).clamp(0, side - 1);
            for py in page(first[1])..=page(last[1]) {
                for px in page(first[0])..=page(last[0]) {
                    let e = entry(&frame.views, level, [px, py]);
                    if frame.flags[e] & RENDERED == 0 {
                        continue;
                    }
                    let clip = |t: i64, p: i64| t.clamp(p * page_texels, p * page_texels + 127);
                    let covers = (clip(first[1], py)..=clip(last[1], py))
                        .step_by(BLOCK as usize)
                        .chain(std::iter::once(clip(last[1], py)))
                        .any(|ty| {
                            (clip(first[0], px)..=clip(last[0], px))
                                .step_by(BLOCK as usize)
                                .chain(std::iter::once(clip(last[0], px)))
                                .any(|tx| mask_has(masks, block_of(&frame.views, level, tx, ty)))
                        });
                    pairs += u32::from(covers);
                }
            }
        }
    }
    pairs
}

fn masked(v: VirtualSettings) -> VirtualSettings {
    VirtualSettings {
        receiver_mask: true,
        ..v
    }
}

fn uncached() -> VirtualSettings {
    VirtualSettings {
        cache: false,
        ..VirtualSettings::default()
    }
}

#[test]
fn the_mask_holds_the_blocks_pixels_read_and_culls_the_casters_over_none() {
    let scene = scene(Sun::default());
    let v = masked(uncached());
    let mut frames = Frames::new(&scene);
    let frame = frames.frame(&scene, &camera(), &settings(v));
    let masks = frames
        .renderer
        .virtual_receiver_masks(gpu())
        .expect("reads back");
    let marked = entries_with(&frame.flags, MARKED);
    // A page is marked exactly where one of its blocks is.
    for (e, mask) in masks.iter().enumerate() {
        let has_blocks = mask[0] | mask[1] != 0;
        assert_eq!(has_blocks, marked.binary_search(&e).is_ok(), "entry {e}");
    }
    let gpu_blocks: Vec<Block> = masks
        .iter()
        .enumerate()
        .flat_map(|(e, m)| {
            (0..64u32)
                .filter(|b| m[(b / 32) as usize] & (1 << (b % 32)) != 0)
                .map(move |b| (e, b))
        })
        .collect();
    let (sure, possible) = cpu_blocks(&scene, &frame, v);
    assert!(!sure.is_empty());
    let missing: Vec<_> = sure
        .iter()
        .filter(|b| gpu_blocks.binary_search(b).is_err())
        .collect();
    assert!(missing.is_empty(), "the GPU left out {missing:?}");
    let extra: Vec<_> = gpu_blocks
        .iter()
        .filter(|b| possible.binary_search(b).is_err())
        .collect();
    assert!(extra.is_empty(), "no pixel reads {extra:?}");

    // The cull: exactly the pairs over a read block; the rest are the ones left out.
    let p = frame.pages;
    assert!(p.receiver_mask);
    assert_eq!(p.caster_pages, expected_pairs(&scene, &frame, &masks));
    assert!(p.caster_pages_masked > 0, "{p:?}");
    // Every page drawn again where it is, the mask off.
    let whole = frames.frame(&scene, &camera(), &settings(uncached()));
    assert_eq!(whole.pages.caster_pages_masked, 0);
    assert_eq!(
        whole.pages.caster_pages,
        p.caster_pages + p.caster_pages_masked
    );
    // Left out only where no pixel reads: the same picture.
    assert_eq!(entries_with(&whole.flags, MARKED), marked);
    let differing = (0..frame.capture.shadow.len())
        .filter(|&i| frame.capture.shadow[i] != whole.capture.shadow[i])
        .count();
    assert_eq!(differing, 0);
}

/// With the cache on, the pages the mask left partial are drawn again the next frame: whole
/// where the cull made them invalid (one layer per page, or static casters left out in a
/// frame that drew every page, the first), their movable layer where only movable casters
/// were left out. The rest stay cached.
#[test]
fn a_page_left_partial_is_drawn_again_the_next_frame() {
    let scene = scene(Sun::default());
    for apart in [false, true] {
        let v = masked(VirtualSettings {
            separate_static: apart,
            ..VirtualSettings::default()
        });
        let mut frames = Frames::new(&scene);
        let first = frames.frame(&scene, &camera(), &settings(v));
        let partial = entries_with(&first.flags, PARTIAL);
        let invalid = entries_with(&first.flags, INVALID);
        assert!(!partial.is_empty(), "apart {apart}: {:?}", first.pages);
        assert!(invalid.iter().all(|e| partial.binary_search(e).is_ok()));
        if !apart {
            assert_eq!(
                invalid, partial,
                "one layer: a partial page is drawn again whole"
            );
        }
        let second = frames.frame(&scene, &camera(), &settings(v));
        let marked = entries_with(&second.flags, MARKED);
        assert_eq!(marked, entries_with(&first.flags, MARKED));
        let among = |set: &[usize], e: &usize| set.binary_search(e).is_ok();
        let drawn: Vec<usize> = marked
            .iter()
            .copied()
            .filter(|e| among(&invalid, e))
            .collect();
        let refreshed: Vec<usize> = marked
            .iter()
            .copied()
            .filter(|e| among(&partial, e) && !among(&invalid, e))
            .collect();
        assert!(!drawn.is_empty() || !refreshed.is_empty());
        if apart {
            assert!(
                !refreshed.is_empty(),
                "the movable box's layer is refreshed"
            );
        }
        assert_eq!(
            entries_with(&second.flags, RENDERED),
            drawn,
            "apart {apart}"
        );
        assert_eq!(
            entries_with(&second.flags, REFRESHED),
            refreshed,
            "apart {apart}"
        );
        assert_eq!(second.pages.pages_invalidated as usize, invalid.len());
        assert_eq!(second.capture.shadow, first.capture.shadow, "apart {apart}");
    }
}
