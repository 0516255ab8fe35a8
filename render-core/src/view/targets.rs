//! The camera's render targets. Recreated when the view size changes.

/// Colour (what the user sees), object ids, depth, the visible surface (position and normal)
/// and shadow factor of the camera view.
pub struct ViewTargets {
    pub width: u32,
    pub height: u32,
    pub color: wgpu::Texture,
    pub color_view: wgpu::TextureView,
    /// The colour target read as plain `Rgba8Unorm` (sRGB-encoded bytes), as egui displays it.
    pub color_view_unorm: wgpu::TextureView,
    pub ids: wgpu::Texture,
    pub ids_view: wgpu::TextureView,
    pub depth: wgpu::Texture,
    pub depth_view: wgpu::TextureView,
    /// The visible surface as the prepass saw it: world position and geometric normal, the
    /// inputs of every shadow lookup (FRAG's mask reads them instead of drawing again).
    pub positions: wgpu::Texture,
    pub positions_view: wgpu::TextureView,
    pub normals: wgpu::Texture,
    pub normals_view: wgpu::TextureView,
    pub shadow: wgpu::Texture,
    pub shadow_view: wgpu::TextureView,
}

/// sRGB colour; what screenshots save.
pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// Instance index + 1 per pixel, 0 for sky.
pub const ID_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
/// Reversed depth (1 near, 0 far); copyable for tests.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// World position (xyz) and geometric normal (xyz) of the visible surface, exactly as the
/// camera's fragment shaders compute them.
pub const SURFACE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// Fraction of shadow taps that see the sun, per pixel (1 for sky and non-receivers): red from
/// the method's map, green from the reference map when measuring (else the same as red).
pub const SHADOW_FACTOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg8Unorm;

impl ViewTargets {
    /// Targets of at least 1x1 texels.
    pub fn new(device: &wgpu::Device, width: u32, height: u32) -> Self {
        let (width, height) = (width.max(1), height.max(1));
        let make = |label: &str, format: wgpu::TextureFormat, extra: wgpu::TextureUsages| {
            let texture = device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width,
                    height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                    | wgpu::TextureUsages::COPY_SRC
                    | extra,
                view_formats: if format == COLOR_FORMAT {
                    &[wgpu::TextureFormat::Rgba8Unorm]
                } else {
                    &[]
                },
            });
            let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
            (texture, view)
        };
        let (color, color_view) = make(
            "ViewTargets::color",
            COLOR_FORMAT,
            wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let color_view_unorm = color.create_view(&wgpu::TextureViewDescriptor {
            label: Some("ViewTargets::color_unorm"),
            format: Some(wgpu::TextureFormat::Rgba8Unorm),
            ..Default::default()
        });
        let (ids, ids_view) = make(
            "ViewTargets::ids",
            ID_FORMAT,
            wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let (depth, depth_view) = make(
            "ViewTargets::depth",
            DEPTH_FORMAT,
            wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let (positions, positions_view) = make(
            "ViewTargets::positions",
            SURFACE_FORMAT,
            wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let (normals, normals_view) = make(
            "ViewTargets::normals",
            SURFACE_FORMAT,
            wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let (shadow, shadow_view) = make(
            "ViewTargets::shadow",
            SHADOW_FACTOR_FORMAT,
            wgpu::TextureUsages::TEXTURE_BINDING,
        );
        Self {
            width,
            height,
            color,
            color_view,
            color_view_unorm,
            ids,
            ids_view,
            depth,
            depth_view,
            positions,
            positions_view,
            normals,
            normals_view,
            shadow,
            shadow_view,
        }
    }
}
