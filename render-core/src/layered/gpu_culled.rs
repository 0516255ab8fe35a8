//! Many lights culled by the GPU methods of `culling/` (receiver masks, DigitalRune's volumes,
//! the oracle...) per light view, as the map technique culls each cascade: the views go to a
//! map technique of their own (`GivenViews`, a layer each), which culls them, renders a pass
//! per map, and draws the reference maps when the frame measures. The light term reads its
//! maps, reference maps and caster ids through the lights' group (`LayeredMaps::group_over`),
//! so culling error and the oracle are counted per light view.
//!
//! Long-lived: that technique, made on first use (its culling pipelines take a while to
//! build). Per frame: the views and the light group.

use super::targets::LayeredMaps;
use crate::gpu::GpuContext;
use crate::shadow_map::{GivenViews, MapTechnique};
use crate::shadow_view::{ShadowSettings, ShadowView};
use crate::technique::{DrawInput, ShadowPasses, ShadowTechnique, TechniqueInput};

pub struct GpuCulledMaps {
    /// Group 0 of scene passes and one view alone, for making the technique.
    layouts: [wgpu::BindGroupLayout; 2],
    maps: Option<MapTechnique>,
    /// The frame's shadow settings at the lights' map size.
    shadow: ShadowSettings,
}

impl GpuCulledMaps {
    pub fn new(layouts: [&wgpu::BindGroupLayout; 2]) -> Self {
        Self {
            layouts: layouts.map(Clone::clone),
            maps: None,
            shadow: ShadowSettings::default(),
        }
    }

    /// The views, culled and rendered from now on by the map technique at maps `resolution`
    /// texels square (its own range: [`Self::resolution`]), as it places them.
    pub fn prepare(
        &mut self,
        ctx: &GpuContext,
        input: &TechniqueInput<'_>,
        (views, resolution): (Vec<ShadowView>, u32),
    ) -> Vec<ShadowView> {
        self.shadow = ShadowSettings {
            resolution,
            ..*input.shadow
        };
        let layouts = &self.layouts;
        let maps = self
            .maps
            .get_or_insert_with(|| MapTechnique::new(ctx, &layouts[0], &layouts[1]));
        maps.set_layout(Box::new(GivenViews(views)));
        maps.prepare(ctx, &at_size(input, &self.shadow))
    }

    /// The map size the map technique renders for a request, within `max` (the lights' own
    /// limit).
    pub fn resolution(requested: u32, max: u32) -> u32 {
        requested.clamp(ShadowSettings::MIN_RESOLUTION, max)
    }

    /// The prepared views' casters culled and rendered, and the lights' light group over
    /// those maps.
    pub fn draw(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        (input, draw): (&TechniqueInput<'_>, &DrawInput<'_>),
        lights: &mut LayeredMaps,
    ) -> ShadowPasses {
        let maps = self.maps.as_mut().expect("prepared before drawn");
        let passes = maps.draw(encoder, &at_size(input, &self.shadow), draw);
        ShadowPasses {
            light_group: lights.group_over(&draw.ctx.device, maps.map_arrays()),
            outcomes: passes.outcomes,
        }
    }

    /// The technique, once made.
    pub fn technique(&self) -> Option<&MapTechnique> {
        self.maps.as_ref()
    }

    pub fn technique_mut(&mut self) -> Option<&mut MapTechnique> {
        self.maps.as_mut()
    }
}

/// `input` with `shadow` in place of its shadow settings.
fn at_size<'a>(input: &TechniqueInput<'a>, shadow: &'a ShadowSettings) -> TechniqueInput<'a> {
    TechniqueInput {
        scene: input.scene,
        scene_gpu: input.scene_gpu,
        camera: input.camera,
        aspect: input.aspect,
        method: input.method,
        shadow,
        direction_to_sun: input.direction_to_sun,
        point_light: input.point_light,
        measure: input.measure,
        measure_fill: input.measure_fill,
        volumes: input.volumes,
        layered: input.layered,
        virtual_maps: input.virtual_maps,
        frame_index: input.frame_index,
        visible_receivers: input.visible_receivers,
        visible_depths_m: input.visible_depths_m,
    }
}
