//! Static occlusion (`--static-occlusion`, on by default where static casters are apart): a
//! movable box wholly behind a cached page's static casters, as the light sees them (block by
//! block of 16 x 16 texels), neither makes the page's movable layer stale when it moves nor
//! is drawn into it. Here a car moves in the shadow of a static roof: the pages it stays
//! behind in keep their layers, those it leaves or enters in the sun are refreshed, the car is
//! left out of refreshed pages where it hides, and every picture is that of every page drawn
//! again where it is.

use glam::{Mat4, Vec3};
use render_core::frame::FrameSettings;
use render_core::geom::Camera;
use render_core::scene::{Instance, Mobility, PointShadow, Scene, Sun};
use render_core::shadow_view::{ShadowView, VirtualSettings};
use shadowlab_tests::virtual_pages::{
    Frame, Frames, MARKED, REFRESHED, RENDERED, RESIDENT, contains, entries_of_blocks,
    entries_with, merged_blocks, pairs_apart, reading_stale, settings, touched_blocks,
    touched_entries,
};
use shadowlab_tests::{box_mesh, gpu};

/// A page whose movable layer a moved box left stale (`virtual_maps/pages.wgsl`).
const DYNAMIC_STALE: u32 = 32;
const CAR: usize = 2;
/// The roof's top, metres above the ground.
const ROOF_TOP_M: f32 = 3.4;

/// A 40 m ground, a static roof of 10 x 10 m whose top is 3.4 m up, and a 1.6 x 1 x 1 m car
/// on the ground in the middle of the roof's shadow (the roof stands towards the sun from
/// it, by the height over the sun's slope).
fn scene() -> Scene {
    let sun = Sun::default();
    let to_sun = sun.direction_to_sun;
    let over_car = Vec3::new(to_sun.x, 0.0, to_sun.z) * (ROOF_TOP_M - 0.2) / to_sun.y;
    let ground = box_mesh("ground", Vec3::new(20.0, 0.5, 20.0));
    let roof = box_mesh("roof", Vec3::new(5.0, 0.2, 5.0));
    let car = box_mesh("car", Vec3::new(0.8, 0.5, 0.5));
    let at = |x: Vec3| Mat4::from_translation(x);
    let mut instances = vec![
        Instance::new("ground", 0, &ground, at(Vec3::new(0.0, -0.5, 0.0))),
        Instance::new(
            "roof",
            1,
            &roof,
            at(over_car + Vec3::Y * (ROOF_TOP_M - 0.2)),
        ),
        Instance::new("car", 2, &car, at(Vec3::new(0.0, 0.5, 0.0))),
    ];
    instances[CAR].mobility = Mobility::Dynamic;
    Scene::new("test:roof", vec![ground, roof, car], instances, sun)
}

/// From beside the roof, low, towards the car under it.
fn camera() -> Camera {
    Camera::look_at(
        Vec3::new(-11.0, 2.5, 9.0),
        Vec3::new(0.0, 0.5, 0.0),
        60f32.to_radians(),
        0.1,
        500.0,
    )
}

fn apart(occlusion: bool) -> FrameSettings {
    settings(VirtualSettings {
        separate_static: true,
        static_occlusion: occlusion,
        ..VirtualSettings::default()
    })
}

/// Moves the car by `by`; returns the entries its old and new bounds touch, each with the
/// blocks of its page they cover.
fn move_car(
    frames: &mut Frames,
    scene: &mut Scene,
    views: &[ShadowView],
    by: Vec3,
) -> Vec<(usize, [u32; 2])> {
    let old = scene.instances[CAR].aabb_in_world;
    let moved = Mat4::from_translation(by) * scene.instances[CAR].world_from_local;
    scene.set_world_from_local(CAR, moved);
    frames
        .scene_gpu
        .update_instances(gpu(), scene, &[CAR as u32]);
    let new = scene.instances[CAR].aabb_in_world;
    merged_blocks(
        touched_blocks(views, old.min, old.max),
        touched_blocks(views, new.min, new.max),
    )
}

/// Asserts that sorted entries `fewer` are some of `more`, not all.
fn strictly_within(fewer: &[usize], more: &[usize]) {
    assert!(fewer.iter().all(|&e| contains(more, e)));
    assert!(
        fewer.len() < more.len(),
        "{} of {}",
        fewer.len(),
        more.len()
    );
}

/// Where the roof stands: above the car's place along the sun.
fn over_car(scene: &Scene) -> Vec3 {
    scene.instances[1].aabb_in_world.center()
}

#[track_caller]
fn same_picture(a: &Frame, b: &Frame) {
    // Where they differ: the pixel, its light in each and what it shows.
    let w = a.capture.width as usize;
    let differing: Vec<_> = (0..a.capture.shadow.len())
        .filter(|&i| a.capture.shadow[i] != b.capture.shadow[i])
        .map(|i| {
            let (x, y) = (i % w, i / w);
            let (cached, fresh) = (a.capture.shadow[i], b.capture.shadow[i]);
            format!(
                "({x}, {y}) {cached} vs {fresh} on object {}",
                a.capture.ids[i]
            )
        })
        .collect();
    assert!(
        differing.is_empty(),
        "{} pixels whose light differs, the first: {:?}",
        differing.len(),
        &differing[..differing.len().min(8)]
    );
}

/// The finest level's entry that the car's centre lies in and pixels marked: a page the
/// camera reads the car's surroundings through.
fn finest_marked_page_at_the_car(scene: &Scene, frame: &Frame) -> usize {
    let centre = scene.instances[CAR].aabb_in_world.center();
    let marked = entries_with(&frame.flags, MARKED);
    touched_entries(&frame.views, centre, centre)
        .into_iter()
        .filter(|&e| contains(&marked, e))
        .min()
        .expect("pixels read a page at the car")
}

#[test]
fn a_car_moving_in_a_static_shadow_leaves_the_pages_it_hides_in_fresh() {
    let by = Vec3::new(0.7, 0.0, 0.4);
    let run = |occlusion: bool| {
        let mut scene = scene();
        let settings = apart(occlusion);
        let mut frames = Frames::new(&scene);
        let first = frames.frame(&scene, &camera(), &settings);
        let stale = move_car(&mut frames, &mut scene, &first.views, by);
        let second = frames.frame(&scene, &camera(), &settings);
        // The pages the car touched, read and resident before, whose pixels read a block it
        // covered: what the move refreshes without occlusion.
        let resident = entries_with(&first.flags, RESIDENT);
        let touched = entries_of_blocks(&stale);
        let candidates: Vec<usize> = entries_with(&second.flags, MARKED)
            .into_iter()
            .filter(|&e| contains(&touched, e) && contains(&resident, e))
            .collect();
        let reading = reading_stale(&frames.renderer, &candidates, &stale);
        // The reference: every page drawn again where it is.
        same_picture(&second, &frames.redrawn(&scene, &camera(), &settings));
        (scene, first, second, reading)
    };
    let (scene, first, on, _) = run(true);
    let (_, first_off, off, read_and_touched) = run(false);
    // Allocation is ordered, so both renderers hold the same pages at the same places:
    // occlusion changes no pixel of the first frame, nor of the second.
    assert_eq!(first.capture.shadow, first_off.capture.shadow);
    same_picture(&on, &off);
    assert_eq!((on.pages.moved_boxes, off.pages.moved_boxes), (2, 2));

    // Without occlusion every page the car touched whose pixels read a block it covered is
    // refreshed.
    assert_eq!(entries_with(&off.flags, REFRESHED), read_and_touched);
    assert_eq!(off.pages.moved_pages_occluded, 0);
    assert!(!off.pages.static_occlusion && on.pages.static_occlusion);

    // With it, the page the camera reads the car's surroundings through stays as it was:
    // the car hides behind the roof there before and after.
    let page = finest_marked_page_at_the_car(&scene, &on);
    assert!(contains(&read_and_touched, page));
    assert_eq!(
        on.flags[page] & (RESIDENT | REFRESHED | RENDERED | DYNAMIC_STALE),
        RESIDENT,
        "page {page}: {:#x}",
        on.flags[page]
    );
    let refreshed_on = entries_with(&on.flags, REFRESHED);
    strictly_within(&refreshed_on, &read_and_touched);
    assert!(on.pages.moved_pages_occluded > 0, "{:?}", on.pages);
    assert_eq!(on.pages.pages_refreshed as usize, refreshed_on.len());
}

/// 7 m towards the camera: out from under the roof's shadow into the sun.
const OUT: Vec3 = Vec3::new(-6.5, 0.0, 3.0);

/// The car's trip out: the scene, its renderer, the first frame (under the roof) and the
/// frame after it drove `OUT`, both cached, static occlusion on.
fn out_into_the_sun() -> (Scene, Frames, Frame, Frame) {
    let mut scene = scene();
    let mut frames = Frames::new(&scene);
    let first = frames.frame(&scene, &camera(), &apart(true));
    move_car(&mut frames, &mut scene, &first.views, OUT);
    let sunny = frames.frame(&scene, &camera(), &apart(true));
    (scene, frames, first, sunny)
}

#[test]
fn a_car_leaving_the_shadow_refreshes_its_new_pages_and_coming_back_is_left_out_where_it_hides() {
    let settings = apart(true);
    let (scene, mut frames, first, sunny) = out_into_the_sun();
    assert_ne!(
        first.capture.shadow, sunny.capture.shadow,
        "the car's shadow shows"
    );
    // In the sun, nothing static is nearer the light than the car over its new pages: every
    // one that was resident and whose pixels read a block the car now covers is refreshed.
    let new = scene.instances[CAR].aabb_in_world;
    let resident = entries_with(&first.flags, RESIDENT);
    let refreshed = entries_with(&sunny.flags, REFRESHED);
    let new_blocks = touched_blocks(&sunny.views, new.min, new.max);
    let at_new: Vec<usize> = entries_of_blocks(&new_blocks)
        .into_iter()
        .filter(|&e| contains(&entries_with(&sunny.flags, MARKED), e) && contains(&resident, e))
        .collect();
    let reading_new = reading_stale(&frames.renderer, &at_new, &new_blocks);
    assert!(!reading_new.is_empty());
    assert!(reading_new.iter().all(|&e| contains(&refreshed, e)));
    assert_eq!(sunny.pages.caster_pages_occluded, 0, "{:?}", sunny.pages);
    assert_eq!(sunny.pages.caster_pages, pairs_apart(&scene, &sunny));
    same_picture(&sunny, &frames.redrawn(&scene, &camera(), &settings));

    // Back under the roof, on a second trip (the reference drew every page of the first one
    // again): the pages of its sunny place are refreshed, and where one of them also holds
    // its new place behind the roof, the car is left out of it.
    let (mut scene, mut frames, _, sunny) = out_into_the_sun();
    move_car(&mut frames, &mut scene, &sunny.views, -OUT);
    let back = frames.frame(&scene, &camera(), &settings);
    same_picture(&back, &frames.redrawn(&scene, &camera(), &settings));
    let p = back.pages;
    assert!(p.pages_refreshed > 0, "{p:?}");
    assert!(p.caster_pages_occluded > 0, "{p:?}");
    // The cull leaves out only what occlusion counts: the rest is the page-exact cull's.
    assert_eq!(
        p.caster_pages + p.caster_pages_occluded,
        pairs_apart(&scene, &back)
    );
}

#[test]
fn under_a_point_light_the_car_hides_behind_the_roof_in_the_faces_pages_too() {
    let light = |scene: &Scene, s: FrameSettings| FrameSettings {
        point_light: Some(PointShadow::omni(over_car(scene) + Vec3::Y * 5.0, 2.0e6)),
        ..s
    };
    let run = |occlusion: bool| {
        let mut scene = scene();
        let settings = light(&scene, apart(occlusion));
        let mut frames = Frames::new(&scene);
        frames.frame(&scene, &camera(), &settings);
        move_car(&mut frames, &mut scene, &[], Vec3::new(0.7, 0.0, 0.4));
        let second = frames.frame(&scene, &camera(), &settings);
        // The reference: every page drawn again where it is.
        same_picture(&second, &frames.redrawn(&scene, &camera(), &settings));
        second
    };
    let on = run(true);
    let off = run(false);
    assert_eq!(on.views.len(), 156, "the cube's levels");
    same_picture(&on, &off);
    let refreshed_off = entries_with(&off.flags, REFRESHED);
    let refreshed_on = entries_with(&on.flags, REFRESHED);
    assert!(!refreshed_off.is_empty());
    strictly_within(&refreshed_on, &refreshed_off);
    assert!(on.pages.moved_pages_occluded > 0, "{:?}", on.pages);
}
