//! Where the many-lights technique's views render: a layer each of a depth array (the
//! traditional and multiview paths), or a tile each of an atlas whose pages are the array's
//! layers (the atlas path). The depth array and the light records are what the light term
//! reads (group 1 of the shading pass), with the reference maps and their caster ids where
//! the maps were culled on the GPU (the map technique's arrays, `mod.rs`).

use crate::gpu::{
    Asked, GpuContext, bind_group_layout, buffer_entry, storage, texture, view_entry,
};
use crate::shadow_view::{LayeredPath, SHADOW_FORMAT, ViewTarget};

use super::lights::LightRecord;

/// Bytes before the first record: the count (`layered/light.wgsl` `Lights`).
const RECORDS_OFFSET: u64 = 16;

/// Where `views` maps of `resolution` texels render for `path`, within the device's limits:
/// each view's target, the side of a layer and the number of layers. Views past what the
/// limits allow are left out (the caller reports it).
pub fn place(
    path: LayeredPath,
    views: usize,
    resolution: u32,
    limits: &wgpu::Limits,
) -> (Vec<ViewTarget>, u32, u32) {
    let max_layers = limits.max_texture_array_layers.max(1) as usize;
    match path {
        LayeredPath::Traditional | LayeredPath::Multiview => {
            let n = views.min(max_layers);
            let targets = (0..n as u32)
                .map(|v| ViewTarget::layer(v, resolution))
                .collect();
            (targets, resolution, n.max(1) as u32)
        }
        LayeredPath::Atlas => {
            let fit = (limits.max_texture_dimension_2d / resolution.max(1)).max(1) as usize;
            let per_row = (views as f64).sqrt().ceil().max(1.0) as usize;
            let per_row = per_row.min(fit);
            let per_page = per_row * per_row;
            let n = views.min(per_page * max_layers);
            let targets = (0..n)
                .map(|v| {
                    let tile = v % per_page;
                    ViewTarget {
                        layer: (v / per_page) as u32,
                        origin: [
                            (tile % per_row) as u32 * resolution,
                            (tile / per_row) as u32 * resolution,
                        ],
                        size: resolution,
                    }
                })
                .collect();
            let layers = n.div_ceil(per_page).max(1) as u32;
            (targets, per_row as u32 * resolution, layers)
        }
    }
}

/// The depth array every path renders into, and the light records; recreated as they grow.
pub struct LayeredMaps {
    pub light_layout: wgpu::BindGroupLayout,
    pub texture: wgpu::Texture,
    /// Every layer, for the light term.
    pub array: wgpu::TextureView,
    /// Each layer alone (the traditional and atlas passes).
    pub layers: Vec<wgpu::TextureView>,
    side: u32,
    records: wgpu::Buffer,
    /// Stands in for the reference's caster ids where there is no reference (never read).
    no_ids: wgpu::TextureView,
    pub light_group: wgpu::BindGroup,
    /// The group over maps rendered elsewhere, with their generation ([`Self::group_over`]).
    over: Option<(u64, wgpu::BindGroup)>,
    /// x: a layer's side in texels, as the atlas paths' vertex stages read it (uniform).
    pub page: wgpu::Buffer,
    /// Multiview: the layers in consecutive groups of `group`, a view each (a pass's target).
    pub groups: Vec<wgpu::TextureView>,
    group: u32,
}

impl LayeredMaps {
    pub fn new(ctx: &GpuContext) -> Self {
        let device = &ctx.device;
        let light_layout = bind_group_layout(
            device,
            "Layered::light_layout",
            wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE,
            &[
                texture(
                    wgpu::TextureSampleType::Depth,
                    wgpu::TextureViewDimension::D2Array,
                ),
                storage(true),
                texture(
                    wgpu::TextureSampleType::Depth,
                    wgpu::TextureViewDimension::D2Array,
                ),
                texture(
                    wgpu::TextureSampleType::Uint,
                    wgpu::TextureViewDimension::D2Array,
                ),
            ],
        );
        let (texture, array, layers) = depth_array(ctx, 64, 1);
        let records = records_buffer(device, 1);
        let no_ids = no_ids(device);
        let light_group = light_group(device, &light_layout, [&array, &array, &no_ids], &records);
        Self {
            light_layout,
            texture,
            array,
            layers,
            side: 64,
            records,
            no_ids,
            light_group,
            over: None,
            page: page_buffer(device, 64),
            groups: Vec::new(),
            group: 0,
        }
    }

    /// A depth array `side` texels square with `layers` layers, its layers in consecutive
    /// groups of `group` for multiview (0: none), and room for `records`; the records written
    /// after the header, which also says how many first views are the sun's (`sun_views`) and
    /// whether the light group will bind reference maps (`reference`, [`Self::group_over`]).
    pub fn ensure(
        &mut self,
        ctx: &GpuContext,
        (side, layers, group): (u32, u32, u32),
        (records, sun_views, reference): (&[LightRecord], u32, bool),
    ) {
        let device = &ctx.device;
        let mut changed = false;
        let resized = self.side != side || self.layers.len() != layers as usize;
        if resized || self.group != group {
            self.group = group;
            self.groups.clear();
        }
        if resized {
            (self.texture, self.array, self.layers) = depth_array(ctx, side, layers);
            if self.side != side {
                let page = [side as f32, 0.0, 0.0, 0.0];
                ctx.queue
                    .write_buffer(&self.page, 0, bytemuck::cast_slice(&page));
            }
            self.side = side;
            changed = true;
        }
        if group > 0 && self.groups.is_empty() {
            self.groups = (0..layers)
                .step_by(group as usize)
                .map(|first| layer_range(&self.texture, first, group.min(layers - first)))
                .collect();
        }
        let bytes = RECORDS_OFFSET + (records.len().max(1) * size_of::<LightRecord>()) as u64;
        if self.records.size() < bytes {
            self.records = records_buffer(device, records.len().next_power_of_two());
            changed = true;
        }
        if changed {
            self.over = None;
            self.light_group = light_group(
                device,
                &self.light_layout,
                [&self.array, &self.array, &self.no_ids],
                &self.records,
            );
        }
        let count = [records.len() as u32, sun_views, u32::from(reference), 0];
        ctx.queue
            .write_buffer(&self.records, 0, bytemuck::cast_slice(&count));
        if !records.is_empty() {
            ctx.queue
                .write_buffer(&self.records, RECORDS_OFFSET, bytemuck::cast_slice(records));
        }
    }
}

fn depth_array(
    ctx: &GpuContext,
    side: u32,
    layers: u32,
) -> (wgpu::Texture, wgpu::TextureView, Vec<wgpu::TextureView>) {
    let asked = Asked {
        what: format!(
            "the many lights' maps: {layers} layers of {side} x {side} texels ({SHADOW_FORMAT:?})"
        ),
        remedy: "fewer lights (--lights) or smaller maps (--shadow-res)",
    };
    let texture = ctx.texture(
        &asked,
        &wgpu::TextureDescriptor {
            label: Some("Layered::maps"),
            size: wgpu::Extent3d {
                width: side,
                height: side,
                depth_or_array_layers: layers,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: SHADOW_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        },
    );
    let array = texture.create_view(&wgpu::TextureViewDescriptor {
        label: Some("Layered::maps"),
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    });
    let each = (0..layers)
        .map(|layer| {
            texture.create_view(&wgpu::TextureViewDescriptor {
                label: Some("Layered::layer"),
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: layer,
                array_layer_count: Some(1),
                ..Default::default()
            })
        })
        .collect();
    (texture, array, each)
}

/// Layers `first..first + count` of `texture` as one array view (a multiview group's target).
pub(super) fn layer_range(texture: &wgpu::Texture, first: u32, count: u32) -> wgpu::TextureView {
    texture.create_view(&wgpu::TextureViewDescriptor {
        label: Some("Layered::layers"),
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        base_array_layer: first,
        array_layer_count: Some(count),
        ..Default::default()
    })
}

/// The page-side uniform, holding `side`.
fn page_buffer(device: &wgpu::Device, side: u32) -> wgpu::Buffer {
    let page = [side as f32, 0.0, 0.0, 0.0];
    wgpu::util::DeviceExt::create_buffer_init(
        device,
        &wgpu::util::BufferInitDescriptor {
            label: Some("Layered::page"),
            contents: bytemuck::cast_slice(&page),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        },
    )
}

fn records_buffer(device: &wgpu::Device, count: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("Layered::lights"),
        size: RECORDS_OFFSET + (count.max(1) * size_of::<LightRecord>()) as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

impl LayeredMaps {
    /// The light term's group over maps rendered elsewhere: the method's maps, the reference
    /// maps and the reference's caster ids (`MapTechnique::map_arrays`), with these records;
    /// made again only when those maps (their `generation`) or the records change.
    pub fn group_over(
        &mut self,
        device: &wgpu::Device,
        (generation, arrays): (u64, [&wgpu::TextureView; 3]),
    ) -> wgpu::BindGroup {
        match &self.over {
            Some((made_for, group)) if *made_for == generation => group.clone(),
            _ => {
                let group = light_group(device, &self.light_layout, arrays, &self.records);
                self.over = Some((generation, group.clone()));
                group
            }
        }
    }
}

/// `arrays`: the maps, the reference maps and the reference's caster ids.
fn light_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    [maps, reference, ids]: [&wgpu::TextureView; 3],
    records: &wgpu::Buffer,
) -> wgpu::BindGroup {
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("Layered::light_group"),
        layout,
        entries: &[
            view_entry(0, maps),
            buffer_entry(1, records),
            view_entry(2, reference),
            view_entry(3, ids),
        ],
    })
}

/// A one-texel array of caster ids (`shadow_map::CASTER_ID_FORMAT`).
fn no_ids(device: &wgpu::Device) -> wgpu::TextureView {
    device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some("Layered::no_ids"),
            size: wgpu::Extent3d {
                width: 1,
                height: 1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: crate::shadow_map::CASTER_ID_FORMAT,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        })
        .create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_atlas_packs_views_in_square_pages_within_the_texture_limit() {
        let limits = wgpu::Limits {
            max_texture_dimension_2d: 4096,
            max_texture_array_layers: 256,
            ..wgpu::Limits::default()
        };
        // 10 maps of 1024: rows of 4, one page of 4096.
        let (targets, side, layers) = place(LayeredPath::Atlas, 10, 1024, &limits);
        assert_eq!((side, layers), (4096, 1));
        assert_eq!(targets[5].origin, [1024, 1024]);
        // 32 maps of 2048: two a row fit, so 8 pages of 4.
        let (targets, side, layers) = place(LayeredPath::Atlas, 32, 2048, &limits);
        assert_eq!((side, layers), (4096, 8));
        assert_eq!((targets[31].layer, targets[31].origin), (7, [2048, 2048]));
        // Layers: one a view, capped by the limit.
        let (targets, side, layers) = place(LayeredPath::Multiview, 300, 512, &limits);
        assert_eq!((targets.len(), side, layers), (256, 512, 256));
        assert_eq!(targets[7], ViewTarget::layer(7, 512));
    }
}
