//! What the virtual maps' tests share: a box over a ground, a camera on it, a renderer that
//! keeps each frame's pages, flags, picture and levels, and the page-table entries a world
//! box touches, computed on the CPU as `virtual_maps/tables.wgsl` finds them.

use glam::{Mat4, Vec3};
use render_core::frame::{
    FrameCapture, FrameInput, FrameRenderer, FrameReport, FrameSettings, ShadowSetup,
};
use render_core::geom::{Aabb, Camera};
use render_core::scene::{Mobility, Scene, Sun};
use render_core::scene_gpu::SceneGpu;
use render_core::shadow_view::{LEVEL_PAGES, PAGE_TEXELS, ShadowView, VirtualSettings};
use render_core::technique::VirtualPages;

use crate::{box_on_plane, gpu};

pub const SIZE: (u32, u32) = (256, 192);
/// Levels of a point light's face or of a spot's chain: the 4 x 4 tiles of the finest mip
/// (16,384 texels), the 2 x 2 of the next, then a level for each of the six mips from 4096
/// texels to 128.
pub const FACE_LEVELS: usize = 26;

/// The names of a face's (or spot's) levels, `name` its own: "{name} mip 0 tile 0,0", ...,
/// "{name} mip 2", ..., "{name} mip 7".
pub fn chain_names(name: &str) -> Vec<String> {
    let mut out = Vec::new();
    for (mip, tiles) in [(0, 4), (1, 2)] {
        for row in 0..tiles {
            for column in 0..tiles {
                out.push(format!("{name} mip {mip} tile {column},{row}"));
            }
        }
    }
    out.extend((2..8).map(|mip| format!("{name} mip {mip}")));
    assert_eq!(out.len(), FACE_LEVELS);
    out
}

/// A page-table entry's flags (`virtual_maps/pages.wgsl`).
pub const MARKED: u32 = 1;
pub const RESIDENT: u32 = 2;
pub const RENDERED: u32 = 4;
pub const REFRESHED: u32 = 64;

/// A 2 x 3 x 1.5 m box 1 m above a 40 m ground; the box moves (a car).
pub fn scene(sun: Sun) -> Scene {
    let mut scene = box_on_plane(20.0, Vec3::new(2.0, 3.0, 1.5), 1.0, sun);
    scene.instances[1].mobility = Mobility::Dynamic;
    scene
}

pub fn camera() -> Camera {
    Camera::look_at(
        Vec3::new(-9.0, 7.0, 11.0),
        Vec3::new(0.0, 0.5, 0.0),
        60f32.to_radians(),
        0.1,
        500.0,
    )
}

pub fn settings(virtual_maps: VirtualSettings) -> FrameSettings {
    FrameSettings {
        setup: ShadowSetup::Virtual,
        measure: true,
        virtual_maps,
        ..FrameSettings::default()
    }
}

/// Renders frames of one renderer and keeps what the tests read.
pub struct Frames {
    pub renderer: FrameRenderer,
    pub scene_gpu: SceneGpu,
}

pub struct Frame {
    pub report: FrameReport,
    pub pages: VirtualPages,
    pub capture: FrameCapture,
    pub flags: Vec<u32>,
    pub views: Vec<ShadowView>,
}

impl Frames {
    pub fn new(scene: &Scene) -> Self {
        Self {
            renderer: FrameRenderer::new(gpu()),
            scene_gpu: SceneGpu::new(gpu(), scene),
        }
    }

    pub fn frame(&mut self, scene: &Scene, camera: &Camera, settings: &FrameSettings) -> Frame {
        let ctx = gpu();
        let input = FrameInput {
            camera,
            width: SIZE.0,
            height: SIZE.1,
            settings,
        };
        let report = self
            .renderer
            .render_and_wait(ctx, scene, &self.scene_gpu, &input)
            .expect("frame renders");
        assert_eq!(report.shadow_failure, None);
        let capture =
            FrameCapture::read(ctx, self.renderer.targets().expect("targets")).expect("readback");
        let flags = self.renderer.virtual_page_flags(ctx).expect("reads back");
        Frame {
            pages: report
                .virtual_pages
                .expect("the virtual maps report their pages"),
            report,
            capture,
            flags,
            views: self.renderer.last_views().to_vec(),
        }
    }
}

impl Frames {
    /// The last frame again with every page drawn again in the physical page it holds (the
    /// cache off for one frame): the exact reference of a cached frame. A fresh renderer's
    /// frame is not one: its pages land elsewhere in the atlas, where the rasteriser's depths
    /// round otherwise in their last bit, which decides a tap whose depth test is that close.
    /// The cache goes on from the pages drawn here.
    pub fn redrawn(&mut self, scene: &Scene, camera: &Camera, settings: &FrameSettings) -> Frame {
        let mut uncached = *settings;
        uncached.virtual_maps.cache = false;
        self.frame(scene, camera, &uncached)
    }

    /// Moves the box (instance 1) 0.9 m along x and 0.4 m along z, across page borders; its
    /// old and new world bounds.
    pub fn move_box(&mut self, scene: &mut Scene) -> [Aabb; 2] {
        let old = scene.instances[1].aabb_in_world;
        let moved =
            Mat4::from_translation(Vec3::new(0.9, 0.0, 0.4)) * scene.instances[1].world_from_local;
        scene.set_world_from_local(1, moved);
        self.scene_gpu.update_instances(gpu(), scene, &[1]);
        [old, scene.instances[1].aabb_in_world]
    }
}

/// Checks that `second` drew again exactly the marked pages that the moved box `touched`
/// (sorted entries) or that were not resident in `first`, and released exactly the resident
/// pages it touched.
pub fn assert_drawn_again_exactly(first: &Frame, second: &Frame, touched: &[usize]) {
    let resident_before = entries_with(&first.flags, RESIDENT);
    let expected: Vec<usize> = entries_with(&second.flags, MARKED)
        .into_iter()
        .filter(|e| touched.binary_search(e).is_ok() || resident_before.binary_search(e).is_err())
        .collect();
    assert!(!expected.is_empty());
    assert_eq!(entries_with(&second.flags, RENDERED), expected);
    let invalidated = resident_before
        .iter()
        .filter(|e| touched.binary_search(e).is_ok())
        .count() as u32;
    assert_eq!(second.pages.pages_invalidated, invalidated);
    assert!(
        second.pages.pages_rendered < second.pages.pages_marked,
        "{:?}",
        second.pages
    );
}

/// The entries whose flags hold `bit`.
pub fn entries_with(flags: &[u32], bit: u32) -> Vec<usize> {
    (0..flags.len()).filter(|&e| flags[e] & bit != 0).collect()
}

/// The page-table entries whose pages (in each level's square) the world box `lo..hi` covers,
/// widened by a texel, as `box_pages` in `virtual_maps/tables.wgsl` finds them.
pub fn touched_entries(views: &[ShadowView], lo: Vec3, hi: Vec3) -> Vec<usize> {
    let mut out: Vec<usize> = touched_blocks(views, lo, hi)
        .into_iter()
        .map(|(e, _)| e)
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}

/// The entries [`touched_entries`] finds, each with the blocks of 16 x 16 texels of its page
/// that the box's widened texels cover (`tables.wgsl` `box_blocks`: bit 8 y + x of block
/// (x, y), over two words), sorted by entry.
pub fn touched_blocks(views: &[ShadowView], lo: Vec3, hi: Vec3) -> Vec<(usize, [u32; 2])> {
    let side = i64::from(LEVEL_PAGES);
    let texels = i64::from(PAGE_TEXELS);
    let mut out = Vec::new();
    for (level, view) in views.iter().enumerate() {
        let (mut min, mut max) = ([f64::MAX; 2], [f64::MIN; 2]);
        for i in 0..8 {
            let corner = Vec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            );
            let p = level_texel(view, corner);
            min = [min[0].min(p[0]), min[1].min(p[1])];
            max = [max[0].max(p[0]), max[1].max(p[1])];
        }
        let first = min.map(|v| (v - 1.0).floor() as i64);
        let last = max.map(|v| (v + 1.0).floor() as i64);
        let page = |v: i64| v.div_euclid(texels);
        for y in page(first[1]).max(0)..=page(last[1]).min(side - 1) {
            for x in page(first[0]).max(0)..=page(last[0]).min(side - 1) {
                let block = |v: i64, origin: i64| ((v - origin) / 16).clamp(0, 7);
                let (bx0, bx1) = (block(first[0], x * texels), block(last[0], x * texels));
                let (by0, by1) = (block(first[1], y * texels), block(last[1], y * texels));
                let mut words = [0u32; 2];
                for by in by0..=by1 {
                    for bx in bx0..=bx1 {
                        let bit = by * 8 + bx;
                        words[(bit / 32) as usize] |= 1 << (bit % 32);
                    }
                }
                out.push((entry(views, level, [x, y]), words));
            }
        }
    }
    out.sort_unstable_by_key(|&(e, _)| e);
    out
}

/// Whether sorted entries `sorted` hold `e`.
pub fn contains(sorted: &[usize], e: usize) -> bool {
    sorted.binary_search(&e).is_ok()
}

/// The (caster, page) pairs a page-exact cull draws where static casters are apart: each
/// static instance into the pages drawn whole that its bounds touch, each movable one into
/// those and the refreshed ones.
pub fn pairs_apart(scene: &Scene, frame: &Frame) -> u32 {
    let rendered = entries_with(&frame.flags, RENDERED);
    let refreshed = entries_with(&frame.flags, REFRESHED);
    let mut pairs = 0;
    for instance in &scene.instances {
        let b = instance.aabb_in_world;
        let movable = instance.mobility != Mobility::Static;
        pairs += touched_entries(&frame.views, b.min, b.max)
            .into_iter()
            .filter(|&e| contains(&rendered, e) || (movable && contains(&refreshed, e)))
            .count();
    }
    pairs as u32
}

/// Two lists of [`touched_blocks`] as one: an entry's blocks in either (a moved box's old and
/// new bounds'), sorted by entry.
pub fn merged_blocks(
    a: Vec<(usize, [u32; 2])>,
    b: Vec<(usize, [u32; 2])>,
) -> Vec<(usize, [u32; 2])> {
    let mut out: Vec<(usize, [u32; 2])> = Vec::new();
    for (e, words) in [a, b].concat() {
        match out.iter_mut().find(|(t, _)| *t == e) {
            Some((_, w)) => *w = [w[0] | words[0], w[1] | words[1]],
            None => out.push((e, words)),
        }
    }
    out.sort_unstable_by_key(|&(e, _)| e);
    out
}

pub fn entries_of_blocks(blocks: &[(usize, [u32; 2])]) -> Vec<usize> {
    blocks.iter().map(|&(e, _)| e).collect()
}

/// The entries among `candidates` whose pixels read (marking's blocks of the last frame, read
/// back) one of the `stale` blocks of their page: the stale pages `tally_pages` refreshes.
pub fn reading_stale(
    renderer: &FrameRenderer,
    candidates: &[usize],
    stale: &[(usize, [u32; 2])],
) -> Vec<usize> {
    let read = renderer.virtual_receiver_masks(gpu()).expect("reads back");
    candidates
        .iter()
        .copied()
        .filter(|&e| {
            stale.iter().any(|&(s, words)| {
                s == e && (words[0] & read[e][0] != 0 || words[1] & read[e][1] != 0)
            })
        })
        .collect()
}

/// What `mark.wgsl` reads of the frame, for the CPU's marking.
pub struct Marking<'a> {
    pub camera: &'a Camera,
    pub views: &'a [ShadowView],
    pub virtual_maps: VirtualSettings,
    /// A pixel's width one metre from the eye.
    pub pixel_at_1m: f64,
    pub normal_offset_texels: f64,
    pub kernel: i64,
}

/// Where level `view` places `p`: its texel (x right, y down), in f64.
pub fn level_texel(view: &ShadowView, p: Vec3) -> [f64; 2] {
    let light = &view.light;
    let grid = light.grid.expect("a level has a texel grid");
    let rows = light.light_from_world.transpose();
    let t = light.light_from_world.w_axis;
    let half = f64::from(LEVEL_PAGES * PAGE_TEXELS) * 0.5;
    let x = f64::from(rows.x_axis.truncate().dot(p) + t.x) * f64::from(grid.per_metre[0]);
    let y = f64::from(rows.y_axis.truncate().dot(p) + t.y) * f64::from(grid.per_metre[1]);
    [
        x - f64::from(grid.centre_texel[0]) + half,
        half - (y - f64::from(grid.centre_texel[1])),
    ]
}

/// The entry of page `page` of level `level`'s square.
pub fn entry(views: &[ShadowView], level: usize, page: [i64; 2]) -> usize {
    let grid = views[level].light.grid.expect("grid");
    let side = i64::from(LEVEL_PAGES);
    let half = f64::from(LEVEL_PAGES * PAGE_TEXELS) * 0.5;
    let first = [
        (f64::from(grid.centre_texel[0]) - half) as i64 / i64::from(PAGE_TEXELS),
        -((f64::from(grid.centre_texel[1]) - half) as i64 / i64::from(PAGE_TEXELS)) - side,
    ];
    let wrapped = [
        (first[0] + page[0]).rem_euclid(side),
        (first[1] + page[1]).rem_euclid(side),
    ];
    level * (side * side) as usize + (wrapped[1] * side + wrapped[0]) as usize
}

impl<'a> Marking<'a> {
    /// What marking reads of a frame of `SIZE` through `camera`, with the default shadow
    /// settings (PCF and normal offset).
    pub fn new(camera: &'a Camera, views: &'a [ShadowView], virtual_maps: VirtualSettings) -> Self {
        let shadow = render_core::shadow_view::ShadowSettings::default();
        Self {
            camera,
            views,
            virtual_maps,
            pixel_at_1m: 2.0 * f64::from((camera.fov_y_rad * 0.5).tan()) / f64::from(SIZE.1),
            normal_offset_texels: f64::from(shadow.normal_offset_texels),
            kernel: i64::from(shadow.pcf.width()),
        }
    }
}

impl Marking<'_> {
    /// The entries the pixel at `p` with normal `n` marks, and whether the answer is certain:
    /// false where its level's octave or a tap's texel lies so near a boundary that the GPU's
    /// f32 (from its own surface point, not this one read back from depth) may fall either side.
    pub fn marks(&self, p: Vec3, n: Vec3) -> Marks {
        let (p64, n64) = (p.as_dvec3(), n.as_dvec3());
        let to_eye = self.camera.eye.as_dvec3() - p64;
        let distance = to_eye.length();
        let cos_view = n64.dot(to_eye / distance).abs().max(0.02);
        let light_dir = self.views[0].light.light_direction.as_dvec3();
        let cos_light = n64.dot(light_dir).abs().max(0.02);
        let texel_m = distance * self.pixel_at_1m * (cos_light / cos_view).sqrt();
        let v = self.virtual_maps;
        let octaves = (texel_m / f64::from(v.finest_texel_m)).log2() + f64::from(v.lod_bias);
        let mut certain = (octaves - octaves.round()).abs() > 0.003;
        let last = v.levels as usize - 1;
        let matched = (octaves.floor().max(0.0) as usize).min(last);
        let side = i64::from(LEVEL_PAGES * PAGE_TEXELS);
        let taps = |level: usize, certain: &mut bool| {
            let texel = f64::from(self.views[level].light.texel_size_m[0]);
            let q = p64 + n64 * (self.normal_offset_texels * texel);
            let t = level_texel(&self.views[level], q.as_vec3());
            let start = t.map(|c| c - 0.5 * (self.kernel - 1) as f64);
            // Near a whole texel the first tap may be either; that matters where the first or
            // the last tap then lands on another page.
            let page_edge = |r: i64| {
                r.rem_euclid(i64::from(PAGE_TEXELS)) == 0
                    || (r + self.kernel - 1).rem_euclid(i64::from(PAGE_TEXELS)) == 0
            };
            let near_whole = |c: &f64| (c - c.round()).abs() < 0.05;
            if start
                .iter()
                .any(|c| near_whole(c) && page_edge(c.round() as i64))
            {
                *certain = false;
            }
            let texels_certain = !start.iter().any(near_whole);
            let first = start.map(|c| c.floor() as i64);
            let last_tap = first.map(|f| f + self.kernel - 1);
            let held = first.iter().all(|&f| f >= 0) && last_tap.iter().all(|&l| l < side);
            held.then(|| {
                let pages = |t: i64| t.div_euclid(i64::from(PAGE_TEXELS));
                let mut entries = Vec::new();
                for y in pages(first[1])..=pages(last_tap[1]) {
                    for x in pages(first[0])..=pages(last_tap[0]) {
                        entries.push(entry(self.views, level, [x, y]));
                    }
                }
                let mut texels = Vec::new();
                for y in first[1]..=last_tap[1] {
                    for x in first[0]..=last_tap[0] {
                        texels.push((level, x, y));
                    }
                }
                (entries, texels, texels_certain)
            })
        };
        // No pixel's page is refused here: no fallback marks.
        let (entries, texels, texels_certain) = (matched..=last)
            .find_map(|level| taps(level, &mut certain))
            .unwrap_or_default();
        Marks {
            entries,
            texels,
            certain,
            texels_certain: texels_certain && certain,
        }
    }
}

/// What one pixel marks, and whether the CPU can be sure of it.
pub struct Marks {
    pub entries: Vec<usize>,
    /// The texels its taps read: level, x, y.
    pub texels: Vec<(usize, i64, i64)>,
    pub certain: bool,
    pub texels_certain: bool,
}

/// The geometric normal of the box-on-plane scene at `p` on instance `id - 1`, towards the eye.
pub fn box_scene_normal(scene: &Scene, id: u32, p: Vec3) -> Vec3 {
    let b = scene.instances[id as usize - 1].aabb_in_world;
    let faces = [
        (p.x - b.min.x, Vec3::NEG_X),
        (b.max.x - p.x, Vec3::X),
        (p.y - b.min.y, Vec3::NEG_Y),
        (b.max.y - p.y, Vec3::Y),
        (p.z - b.min.z, Vec3::NEG_Z),
        (b.max.z - p.z, Vec3::Z),
    ];
    faces
        .iter()
        .min_by(|a, b| a.0.abs().total_cmp(&b.0.abs()))
        .map(|f| f.1)
        .expect("six faces")
}
