//! The volume passes' compute work of one frame (`volumes/find.wgsl`), each a timed step
//! of the silhouettes' scope: the receiver grid, the cull, the big casters' workgroups and
//! the silhouettes and caps. The pipelines are long-lived; `FindInput` is the frame's.
//!
//! How many casters went to workgroups (`volumes/big_casters.wgsl`) is known only on the
//! GPU, so their dispatches are indirect: `size_big_casters` writes the workgroup counts
//! after the cull, and they are copied to a buffer of their own (`SceneVolumes::big_dispatch`)
//! before the big casters' pass, which binds the list itself for writing. Where the cull
//! gathers nothing (standard volumes, exact clamping's given intervals) it lists none, and
//! the indirect dispatches run no workgroup.

use super::pipelines::{BIG_DISPATCH_OFFSET, RECEIVER_CELLS, dispatch_size, group_rows};
use super::scene::SceneVolumes;
use crate::gpu::{GpuContext, Scope, compute_pipeline, pass_label};

/// The find pipelines, compiled once per device.
pub(super) struct FindPasses {
    reset: wgpu::ComputePipeline,
    receivers: wgpu::ComputePipeline,
    /// Each grid cell's start in the view's receiver points, then the points listed there.
    place: wgpu::ComputePipeline,
    list: wgpu::ComputePipeline,
    cull: wgpu::ComputePipeline,
    /// The workgroup counts of the casters too big for `cull`'s workgroup.
    size_big: wgpu::ComputePipeline,
    /// Their workgroups, then one invocation each to finish them.
    gather_big: wgpu::ComputePipeline,
    finish_big: wgpu::ComputePipeline,
    silhouettes: wgpu::ComputePipeline,
    caps: wgpu::ComputePipeline,
}

/// What one frame's find passes read and write.
pub(super) struct FindInput<'a> {
    pub scene: &'a SceneVolumes,
    pub frame_group: &'a wgpu::BindGroup,
    pub find_group: &'a wgpu::BindGroup,
    /// The view's size, pixels.
    pub size: (u32, u32),
}

/// A pipeline and its workgroups: x and y, or read from the big casters' dispatch buffer
/// at a byte offset.
enum Groups {
    Fixed([u32; 2]),
    Indirect(u64),
}

impl FindPasses {
    /// `module` is `volumes/find.wgsl`; `layout` binds the frame's, the scene's and the find
    /// passes' groups.
    pub(super) fn new(
        ctx: &GpuContext,
        module: &wgpu::ShaderModule,
        layout: &wgpu::PipelineLayout,
    ) -> Self {
        let find = |entry: &str| {
            ctx.compute_pipeline_once(&format!("Volumes::find/{entry}"), || {
                compute_pipeline(&ctx.device, module, Some(layout), entry)
            })
        };
        Self {
            reset: find("reset_draws"),
            receivers: find("mark_receivers"),
            place: find("place_cells"),
            list: find("list_receivers"),
            cull: find("cull_casters"),
            size_big: find("size_big_casters"),
            gather_big: find("gather_big_casters"),
            finish_big: find("finish_big_casters"),
            silhouettes: find("find_silhouettes"),
            caps: find("find_caps"),
        }
    }

    /// Encodes the frame's find passes, each a step of `scope`.
    pub(super) fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        scope: &Scope<'_>,
        input: &FindInput<'_>,
    ) {
        let (width, height) = input.size;
        let scene = input.scene;
        let pixels = [width.div_ceil(8), height.div_ceil(8)];
        let steps: [(&str, &[(&wgpu::ComputePipeline, Groups)]); 4] = [
            (
                pass_label::volumes::RECEIVER_GRID,
                &[
                    (&self.reset, Groups::Fixed([1, 1])),
                    (&self.receivers, Groups::Fixed(pixels)),
                    (&self.place, Groups::Fixed([RECEIVER_CELLS.div_ceil(64), 1])),
                    (&self.list, Groups::Fixed(pixels)),
                ],
            ),
            (
                pass_label::volumes::CULL_AND_CLAMP,
                &[
                    (&self.cull, Groups::Fixed(one_group_each(scene.casters))),
                    (&self.size_big, Groups::Fixed([1, 1])),
                ],
            ),
            (
                pass_label::volumes::BIG_CASTERS,
                &[
                    (&self.gather_big, Groups::Indirect(0)),
                    (&self.finish_big, Groups::Indirect(16)),
                ],
            ),
            (
                pass_label::volumes::EDGES,
                &[
                    (
                        &self.silhouettes,
                        Groups::Fixed(dispatch_groups(scene.edge_items)),
                    ),
                    (
                        &self.caps,
                        Groups::Fixed(dispatch_groups(scene.triangle_items)),
                    ),
                ],
            ),
        ];
        for (label, dispatches) in steps {
            scope.step(label, encoder, |encoder| {
                if label == pass_label::volumes::EDGES {
                    // No fan corner yet (`append_fans` in `volumes/records.wgsl`).
                    encoder.clear_buffer(&scene.anchors, 0, None);
                }
                if dispatches
                    .iter()
                    .any(|(_, g)| matches!(g, Groups::Indirect(_)))
                {
                    encoder.copy_buffer_to_buffer(
                        &scene.big,
                        BIG_DISPATCH_OFFSET,
                        &scene.big_dispatch,
                        0,
                        scene.big_dispatch.size(),
                    );
                }
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some(label),
                    timestamp_writes: None,
                });
                pass.set_bind_group(0, input.frame_group, &[]);
                pass.set_bind_group(1, &scene.scene_group, &[]);
                pass.set_bind_group(2, input.find_group, &[]);
                for (pipeline, groups) in dispatches {
                    match groups {
                        Groups::Fixed([x, y]) if x * y > 0 => {
                            pass.set_pipeline(pipeline);
                            pass.dispatch_workgroups(*x, *y, 1);
                        }
                        Groups::Fixed(_) => {}
                        Groups::Indirect(offset) => {
                            pass.set_pipeline(pipeline);
                            pass.dispatch_workgroups_indirect(&scene.big_dispatch, *offset);
                        }
                    }
                }
            });
        }
    }
}

/// Workgroups for `items` work items (none for none).
fn dispatch_groups(items: u32) -> [u32; 2] {
    if items == 0 {
        return [0, 0];
    }
    let (x, y) = dispatch_size(items);
    [x, y]
}

/// One workgroup for each of `items` (`cull_casters`).
fn one_group_each(items: u32) -> [u32; 2] {
    let (x, y) = group_rows(items);
    [x, y]
}
