//! What the virtual maps' tests share: a box over a ground, a camera on it, a renderer that
//! keeps each frame's pages, flags, picture and levels, and the page-table entries a world
//! box touches, computed on the CPU as `virtual_maps/tables.wgsl` finds them.

use glam::{DVec3, Vec3};
use render_core::frame::{
    FrameCapture, FrameInput, FrameRenderer, FrameReport, FrameSettings, ShadowSetup,
};
use render_core::geom::Camera;
use render_core::scene::{Mobility, Scene, Sun};
use render_core::scene_gpu::SceneGpu;
use render_core::shadow_view::{LEVEL_PAGES, PAGE_TEXELS, ShadowView, VirtualSettings};
use render_core::technique::VirtualPages;

use crate::{box_on_plane, gpu};

pub const SIZE: (u32, u32) = (256, 192);
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

/// The entries whose flags hold `bit`.
pub fn entries_with(flags: &[u32], bit: u32) -> Vec<usize> {
    (0..flags.len()).filter(|&e| flags[e] & bit != 0).collect()
}

/// The page-table entries whose pages (in each level's square) the world box `lo..hi` covers,
/// widened by a texel, as `box_pages` in `virtual_maps/tables.wgsl` finds them.
pub fn touched_entries(views: &[ShadowView], lo: Vec3, hi: Vec3) -> Vec<usize> {
    let side = i64::from(LEVEL_PAGES);
    let mut out = Vec::new();
    for (level, view) in views.iter().enumerate() {
        let light = &view.light;
        let grid = light.grid.expect("a level has a texel grid");
        let rows = light.light_from_world.transpose();
        let t = light.light_from_world.w_axis;
        let half = f64::from(LEVEL_PAGES * PAGE_TEXELS) * 0.5;
        let texel = |p: Vec3| {
            let x = f64::from(rows.x_axis.truncate().dot(p) + t.x) * f64::from(grid.per_metre[0]);
            let y = f64::from(rows.y_axis.truncate().dot(p) + t.y) * f64::from(grid.per_metre[1]);
            DVec3::new(
                x - f64::from(grid.centre_texel[0]) + half,
                half - (y - f64::from(grid.centre_texel[1])),
                0.0,
            )
        };
        let (mut min, mut max) = (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN));
        for i in 0..8 {
            let corner = Vec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            );
            let p = texel(corner);
            min = min.min(p);
            max = max.max(p);
        }
        let page = |v: f64| (v / f64::from(PAGE_TEXELS)).floor() as i64;
        let first_page = [
            (f64::from(grid.centre_texel[0]) - half) as i64 / i64::from(PAGE_TEXELS),
            -((f64::from(grid.centre_texel[1]) - half) as i64 / i64::from(PAGE_TEXELS)) - side,
        ];
        for y in page(min.y - 1.0).max(0)..=page(max.y + 1.0).min(side - 1) {
            for x in page(min.x - 1.0).max(0)..=page(max.x + 1.0).min(side - 1) {
                let wrapped = [
                    (first_page[0] + x).rem_euclid(side),
                    (first_page[1] + y).rem_euclid(side),
                ];
                out.push(
                    level * (side * side) as usize + (wrapped[1] * side + wrapped[0]) as usize,
                );
            }
        }
    }
    out.sort_unstable();
    out.dedup();
    out
}
