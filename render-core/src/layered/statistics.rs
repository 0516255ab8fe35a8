//! Pipeline statistics of the maps' passes, where the adapter has them: per pass the vertex
//! shader invocations, the triangles that enter the clipper and those it passes on to be
//! rasterised. The passes are depth only, so there are no fragment invocations to count.

use std::cell::Cell;

use crate::gpu::{GpuContext, GpuError, read_buffer};

/// The most passes a frame counts: one per view, and there are at most 256 views.
const CAPACITY: u32 = 256;
/// Statistics per pass, in the order of their bits.
const PER_PASS: u64 = 3;

/// One pass's counts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct PassCounts {
    pub vertex_invocations: u64,
    /// Triangles the vertex stage handed to the clipper.
    pub clipper_invocations: u64,
    /// Triangles the clipper passed on to be rasterised.
    pub rasterised: u64,
}

/// The query set, its resolve buffer and this frame's next query.
pub struct PassStatistics {
    queries: Option<(wgpu::QuerySet, wgpu::Buffer)>,
    next: Cell<u32>,
}

impl PassStatistics {
    pub fn new(ctx: &GpuContext) -> Self {
        let queries = ctx
            .features()
            .contains(wgpu::Features::PIPELINE_STATISTICS_QUERY)
            .then(|| {
                let set = ctx.device.create_query_set(&wgpu::QuerySetDescriptor {
                    label: Some("Layered::statistics"),
                    ty: wgpu::QueryType::PipelineStatistics(
                        wgpu::PipelineStatisticsTypes::VERTEX_SHADER_INVOCATIONS
                            | wgpu::PipelineStatisticsTypes::CLIPPER_INVOCATIONS
                            | wgpu::PipelineStatisticsTypes::CLIPPER_PRIMITIVES_OUT,
                    ),
                    count: CAPACITY,
                });
                let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("Layered::statistics"),
                    size: u64::from(CAPACITY) * PER_PASS * 8,
                    usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                });
                (set, buffer)
            });
        Self {
            queries,
            next: Cell::new(0),
        }
    }

    /// Starts a frame's count.
    pub fn begin_frame(&self) {
        self.next.set(0);
    }

    /// The query of the next pass, while there is room.
    pub fn next(&self) -> Option<(&wgpu::QuerySet, u32)> {
        let (set, _) = self.queries.as_ref()?;
        let index = self.next.get();
        (index < CAPACITY).then(|| {
            self.next.set(index + 1);
            (set, index)
        })
    }

    /// Resolves this frame's queries into the buffer.
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        if let Some((set, buffer)) = &self.queries
            && self.next.get() > 0
        {
            encoder.resolve_query_set(set, 0..self.next.get(), buffer, 0);
        }
    }

    /// The last frame's counts, a pass each. Blocks: for tests and the bench.
    pub fn read(&self, ctx: &GpuContext) -> Result<Vec<PassCounts>, GpuError> {
        let Some((_, buffer)) = &self.queries else {
            return Ok(Vec::new());
        };
        let passes = u64::from(self.next.get());
        if passes == 0 {
            return Ok(Vec::new());
        }
        let bytes = read_buffer(ctx, buffer, passes * PER_PASS * 8, "pass statistics")?;
        let words: Vec<u64> = bytes
            .chunks_exact(8)
            .map(|b| u64::from_le_bytes(b.try_into().unwrap_or([0; 8])))
            .collect();
        Ok(words
            .chunks_exact(PER_PASS as usize)
            .map(|c| PassCounts {
                vertex_invocations: c[0],
                clipper_invocations: c[1],
                rasterised: c[2],
            })
            .collect())
    }
}
