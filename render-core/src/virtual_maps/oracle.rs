//! The per-page oracle, when measuring: which (caster, page) pairs drawn this frame hold a
//! texel that a visible pixel's tap reads shadowed. `mark_shadowed` (`mark.wgsl`) finds those
//! texels in the atlas the frame drew, in the layer holding the nearest depth; the pairs are
//! then drawn again over the atlas, read-only with an EQUAL depth test (`draw.wgsl`
//! `fs_oracle`), so a pair's fragments run only where its caster holds the depth. Where the
//! frame drew every page it reads (the cache off, or every page invalid), these are the pairs
//! the shadows need, and the pairs drawn over them is the per-page cull's tightness. Not
//! timed: a measurement pass.

use super::VirtualTechnique;
use super::gpu_data::{LEVEL_SLOTS, word};
use super::resources::Tables;
use crate::technique::DrawInput;

impl VirtualTechnique {
    /// After the page draws: the oracle's texels, its pairs, and their counts per level into
    /// the counters. `groups`: the tables', the surface's, the draws' and the oracle's.
    pub(super) fn encode_oracle(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        draw: &DrawInput<'_>,
        scene_gpu: &crate::scene_gpu::SceneGpu,
        (tables, groups): (&Tables, [&wgpu::BindGroup; 4]),
    ) {
        let Some(oracle) = &self.pipelines.oracle else {
            return;
        };
        let [table_group, mark_group, draw_group, oracle_group] = groups;
        encoder.clear_buffer(&tables.oracle_texels, 0, None);
        encoder.clear_buffer(&self.lists.oracle, 0, None);
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("VirtualMaps::oracle_texels"),
                timestamp_writes: None,
            });
            pass.set_bind_group(0, draw.frame_group, &[]);
            pass.set_bind_group(1, table_group, &[]);
            pass.set_bind_group(2, mark_group, &[]);
            pass.set_pipeline(&self.pipelines.mark[4]);
            pass.dispatch_workgroups(
                draw.targets.width.div_ceil(8),
                draw.targets.height.div_ceil(8),
                1,
            );
        }
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("VirtualMaps::oracle"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &tables.atlas_view,
                depth_ops: None,
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, draw.frame_group, &[]);
        pass.set_bind_group(1, draw_group, &[]);
        pass.set_bind_group(2, oracle_group, &[]);
        pass.set_pipeline(oracle);
        self.draw_pairs(&mut pass, scene_gpu, tables);
        drop(pass);
        encoder.copy_buffer_to_buffer(
            &self.lists.oracle,
            0,
            &tables.counters,
            (word::LEVEL_ORACLE * 4) as u64,
            (LEVEL_SLOTS * 4) as u64,
        );
    }
}

/// One (caster, page) pair the last frame drew (`VirtualTechnique::read_pairs`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct DrawnPair {
    /// The caster's instance.
    pub instance: u32,
    /// Its page's table entry (level by level, 1,024 each).
    pub entry: u32,
    /// Drawn into the page's movable layer (static casters apart).
    pub movable_layer: bool,
    /// In the per-page oracle (when the frame measured).
    pub oracle: bool,
}

/// The pair list's bit of the movable layer and the entry's bits (`pages.wgsl`).
pub(super) const DYNAMIC_ONLY: u32 = 0x4000_0000;
pub(super) const ENTRY_BITS: u32 = 0x3fff_ffff;

impl VirtualTechnique {
    /// The last frame's (caster, page) pairs, in the cull's order, and which of them the
    /// per-page oracle holds. Blocks: for tests.
    pub fn read_pairs(
        &self,
        ctx: &crate::gpu::GpuContext,
    ) -> Result<Vec<DrawnPair>, crate::gpu::GpuError> {
        let count = self.latest.as_ref().map_or(0, |(_, c)| c.pairs);
        if count == 0 || count > self.lists.pairs_capacity {
            return Ok(Vec::new());
        }
        let read = crate::gpu::read_buffer;
        let pairs: Vec<u32> = bytemuck::pod_collect_to_vec(&read(
            ctx,
            &self.lists.pairs,
            8 * u64::from(count),
            "pairs",
        )?);
        let oracle: Vec<u32> = bytemuck::pod_collect_to_vec(&read(
            ctx,
            &self.lists.oracle,
            self.lists.oracle.size(),
            "oracle",
        )?);
        let bits = &oracle[LEVEL_SLOTS..];
        Ok((0..count as usize)
            .map(|i| DrawnPair {
                instance: pairs[2 * i],
                entry: pairs[2 * i + 1] & ENTRY_BITS,
                movable_layer: pairs[2 * i + 1] & DYNAMIC_ONLY != 0,
                oracle: bits[i / 32] & (1 << (i % 32)) != 0,
            })
            .collect())
    }
}
