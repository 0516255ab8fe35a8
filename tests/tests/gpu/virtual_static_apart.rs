//! Virtual maps with static casters kept apart (`--separate-static on`, Unreal's
//! `Cache.StaticSeparate`): a moving box leaves the pages it touches resident and draws only
//! itself into them again (their movable layer) where pixels read a block of 16 x 16 texels
//! it made stale, the static ground's depths stay cached, and the picture equals a full
//! re-render with one layer. A page that goes stale while no pixel reads it is drawn again
//! when one reads its stale blocks.

use glam::Vec3;
use render_core::geom::Camera;
use render_core::scene::{Scene, Sun};
use render_core::shadow_view::{ShadowView, VirtualSettings};
use shadowlab_tests::gpu;
use shadowlab_tests::virtual_pages::{
    Frame, Frames, MARKED, REFRESHED, RENDERED, RESIDENT, camera, contains, entries_of_blocks,
    entries_with, entry, level_texel, merged_blocks, pairs_apart, reading_stale, scene, settings,
    touched_blocks, touched_entries,
};

/// A page whose movable layer a moved box left stale (`virtual_maps/pages.wgsl`).
const DYNAMIC_STALE: u32 = 32;

fn apart() -> VirtualSettings {
    VirtualSettings {
        separate_static: true,
        ..VirtualSettings::default()
    }
}

/// Moves the box (instance 1) 0.9 m along x and 0.4 m along z, across page borders; returns
/// the page-table entries its old and new bounds touch, each with the blocks of its page they
/// cover: those of its movable layer the move made stale.
fn move_box(
    frames: &mut Frames,
    scene: &mut Scene,
    views: &[ShadowView],
) -> Vec<(usize, [u32; 2])> {
    let [old, new] = frames.move_box(scene);
    let (before, after) = (
        touched_blocks(views, old.min, old.max),
        touched_blocks(views, new.min, new.max),
    );
    assert_ne!(
        touched_entries(views, old.min, old.max),
        touched_entries(views, new.min, new.max),
        "the box crosses page borders"
    );
    merged_blocks(before, after)
}

/// Pixels whose light differs between two pictures.
fn differing(a: &[u8], b: &[u8]) -> usize {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).filter(|(x, y)| x != y).count()
}

/// The hierarchy of page flags (`virtual_maps/tables.wgsl` `page_hierarchy`) from the
/// flags: per level, mips 1 to 5 of its 32 x 32 pages, bit 0 over a page drawn whole, bit 1
/// over a refreshed one.
fn expected_hierarchy(views: &[ShadowView], flags: &[u32]) -> Vec<u32> {
    let mut cells = vec![0; views.len() * 341];
    for level in 0..views.len() {
        for y in 0..32 {
            for x in 0..32 {
                let f = flags[entry(views, level, [x, y])];
                let bits = u32::from(f & RENDERED != 0) | (u32::from(f & REFRESHED != 0) << 1);
                let mut before = 0;
                for mip in 1..=5 {
                    let side = 32 >> mip;
                    let cell = (y >> mip) * side + (x >> mip);
                    cells[level * 341 + before + cell as usize] |= bits;
                    before += (side * side) as usize;
                }
            }
        }
    }
    cells
}

/// The pages under the casters' boxes (widened by a texel) within each level's square of
/// drawn and refreshed pages, summed over casters and levels: what the cull counts as
/// `cull_pages_spanned`.
fn spanned_pages(scene: &Scene, frame: &Frame) -> u32 {
    let mut total = 0;
    for (level, view) in frame.views.iter().enumerate() {
        let (mut lo, mut hi) = ([i64::MAX; 2], [i64::MIN; 2]);
        for y in 0..32 {
            for x in 0..32 {
                if frame.flags[entry(&frame.views, level, [x, y])] & (RENDERED | REFRESHED) != 0 {
                    lo = [lo[0].min(x), lo[1].min(y)];
                    hi = [hi[0].max(x), hi[1].max(y)];
                }
            }
        }
        if hi[0] < lo[0] {
            continue; // The level draws nothing: the cull leaves it at once.
        }
        for instance in &scene.instances {
            let b = instance.aabb_in_world;
            let (mut t_lo, mut t_hi) = ([f64::MAX; 2], [f64::MIN; 2]);
            for corner in b.corners() {
                let t = level_texel(view, corner);
                t_lo = [t_lo[0].min(t[0]), t_lo[1].min(t[1])];
                t_hi = [t_hi[0].max(t[0]), t_hi[1].max(t[1])];
            }
            let page = |t: f64| ((t / 128.0).floor() as i64).clamp(-1, 32);
            let span = |k: usize| {
                let first = page(t_lo[k] - 1.0).max(0).max(lo[k]);
                let last = page(t_hi[k] + 1.0).min(31).min(hi[k]);
                (last - first + 1).max(0)
            };
            total += span(0) * span(1);
        }
    }
    total as u32
}

#[test]
fn a_moving_box_draws_only_itself_again_into_the_pages_it_touches() {
    let mut scene = scene(Sun::default());
    let settings = settings(apart());
    let mut frames = Frames::new(&scene);
    let first = frames.frame(&scene, &camera(), &settings);
    let p = first.pages;
    assert!(p.separate_static);
    assert!(
        p.pages_marked > 0 && p.pages_rendered == p.pages_marked,
        "{p:?}"
    );
    assert_eq!(p.pages_refreshed, 0);
    assert_eq!(p.caster_pages, pairs_apart(&scene, &first));

    let stale = move_box(&mut frames, &mut scene, &first.views);
    let touched = entries_of_blocks(&stale);
    let second = frames.frame(&scene, &camera(), &settings);
    let q = second.pages;
    assert_eq!(q.moved_boxes, 2);
    assert_eq!(q.pages_invalidated, 0, "no page is released: {q:?}");
    let resident_before = entries_with(&first.flags, RESIDENT);
    let marked = entries_with(&second.flags, MARKED);
    // Whole: only the marked pages that were not there before. Refreshed: the marked pages
    // the box's old or new bounds touch whose pixels read a block it covered.
    let new_pages: Vec<usize> = marked
        .iter()
        .copied()
        .filter(|&e| !contains(&resident_before, e))
        .collect();
    let touched_and_read: Vec<usize> = marked
        .iter()
        .copied()
        .filter(|&e| contains(&touched, e) && contains(&resident_before, e))
        .collect();
    let refreshed = reading_stale(&frames.renderer, &touched_and_read, &stale);
    assert!(!refreshed.is_empty());
    assert!(
        refreshed.len() < touched_and_read.len(),
        "pages whose pixels read none of the stale blocks wait"
    );
    // They stay stale, with those blocks unread (the picture below is a fresh render's).
    let waiting: Vec<usize> = touched
        .iter()
        .copied()
        .filter(|&e| contains(&resident_before, e) && !contains(&refreshed, e))
        .collect();
    assert_eq!(entries_with(&second.flags, DYNAMIC_STALE), waiting);
    assert_eq!(entries_with(&second.flags, RENDERED), new_pages);
    assert_eq!(entries_with(&second.flags, REFRESHED), refreshed);
    assert_eq!(q.pages_refreshed as usize, refreshed.len());
    assert_eq!(q.caster_pages, pairs_apart(&scene, &second));
    // The hierarchy the cull walks holds, in each cell, exactly what its pages did.
    let hierarchy = frames
        .renderer
        .virtual_page_hierarchy(gpu())
        .expect("reads back");
    assert_eq!(hierarchy, expected_hierarchy(&second.views, &second.flags));
    assert!(hierarchy.contains(&3), "cells over both kinds");
    assert_eq!(q.cull_pages_spanned, spanned_pages(&scene, &second));
    assert!(q.cull_flag_reads > 0, "{q:?}");
    let hits = marked.len() - new_pages.len() - refreshed.len();
    let rate = q.cache_hit_rate.expect("pages were marked");
    assert!(
        (rate - hits as f64 / marked.len() as f64).abs() < 1e-12,
        "{q:?}"
    );

    // No stale shadow: the same picture as every page drawn again where it is (both layers;
    // against the exact shadow: virtual_maps.rs `the_hard_cases_give_the_exact_shadow`).
    let redrawn = frames.redrawn(&scene, &camera(), &settings);
    assert_eq!(
        differing(&second.capture.shadow, &redrawn.capture.shadow),
        0
    );
    assert!(
        differing(&first.capture.shadow, &second.capture.shadow) > 0,
        "the shadow moved"
    );

    // Nothing moves: nothing is drawn.
    let third = frames.frame(&scene, &camera(), &settings);
    assert_eq!(
        (third.pages.pages_rendered, third.pages.pages_refreshed),
        (0, 0)
    );
    assert_eq!(third.pages.caster_pages, 0);
    assert_eq!(
        (third.pages.cull_pages_spanned, third.pages.cull_flag_reads),
        (0, 0)
    );
    assert_eq!(differing(&third.capture.shadow, &second.capture.shadow), 0);
}

/// The box moves while the camera looks at the sky: its pages go stale unread and are not
/// drawn; when the camera looks back, exactly those it reads are refreshed.
#[test]
fn a_page_left_stale_while_unread_is_refreshed_when_read_again() {
    let mut scene = scene(Sun::default());
    let settings = settings(apart());
    let mut frames = Frames::new(&scene);
    let first = frames.frame(&scene, &camera(), &settings);
    let look = camera();
    let sky = Camera::look_at(
        look.eye,
        look.eye + Vec3::new(0.05, 1.0, 0.02),
        60f32.to_radians(),
        0.1,
        500.0,
    );
    let stale_blocks = move_box(&mut frames, &mut scene, &first.views);
    let touched = entries_of_blocks(&stale_blocks);
    let away = frames.frame(&scene, &sky, &settings);
    assert_eq!(away.pages.pages_marked, 0, "{:?}", away.pages);
    assert_eq!(
        (away.pages.pages_rendered, away.pages.pages_refreshed),
        (0, 0)
    );
    let resident = entries_with(&away.flags, RESIDENT);
    assert_eq!(resident, entries_with(&first.flags, RESIDENT));
    let stale: Vec<usize> = resident
        .iter()
        .copied()
        .filter(|&e| contains(&touched, e))
        .collect();
    assert!(!stale.is_empty());
    assert_eq!(entries_with(&away.flags, DYNAMIC_STALE), stale);

    let back = frames.frame(&scene, &camera(), &settings);
    let marked = entries_with(&back.flags, MARKED);
    let read_stale: Vec<usize> = marked
        .iter()
        .copied()
        .filter(|&e| contains(&stale, e))
        .collect();
    let refreshed = reading_stale(&frames.renderer, &read_stale, &stale_blocks);
    assert!(!refreshed.is_empty());
    assert_eq!(entries_with(&back.flags, REFRESHED), refreshed);
    let still_stale: Vec<usize> = stale
        .iter()
        .copied()
        .filter(|&e| !contains(&refreshed, e))
        .collect();
    assert_eq!(entries_with(&back.flags, DYNAMIC_STALE), still_stale);
    assert_eq!(
        entries_with(&back.flags, RENDERED),
        marked
            .iter()
            .copied()
            .filter(|&e| !contains(&resident, e))
            .collect::<Vec<_>>()
    );
    let redrawn = frames.redrawn(&scene, &camera(), &settings);
    assert_eq!(differing(&back.capture.shadow, &redrawn.capture.shadow), 0);
}
