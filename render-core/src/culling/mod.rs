//! Choosing shadow casters, per shadow view: the methods of DESIGN.md stage by stage, the
//! stages' counts and what happened to each object. `none` and `vfc` choose on the CPU through
//! the scene's BVH ([`CasterSelection`]); the other methods cull on the GPU ([`GpuCulling`]:
//! receiver masks, max pyramids, two-phase caster tests, DigitalRune's shadow volumes,
//! incremental updates, indirect draws), every view in one dispatch with a block of buffers
//! per view.

pub(crate) mod codes;
mod cpu;
mod gpu;
mod method;
mod stage;

pub use cpu::CasterSelection;
#[cfg(test)]
pub(crate) use gpu::shader_sources;
pub use gpu::{
    CullError, CullFrame, CullPass, CullResult, CullTargets, FragmentMaskSource, GpuCulling,
    MAX_MASK_SIZE, MaskForInset, ViewCull,
};
pub use method::Method;
pub use stage::{CasterOutcome, Stage, StageKind};
