//! Copies of textures and buffers back to the CPU, handling the 256-byte row alignment.

use super::{GpuContext, GpuError};

/// Rows of texels without padding, plus the image size.
#[derive(Clone, Debug)]
pub struct TexelRows {
    pub width: u32,
    pub height: u32,
    pub bytes_per_texel: u32,
    pub bytes: Vec<u8>,
}

/// Reads a whole 2D texture (mip 0, layer 0) and blocks until the copy is done.
pub fn read_texture(
    ctx: &GpuContext,
    texture: &wgpu::Texture,
    aspect: wgpu::TextureAspect,
) -> Result<TexelRows, GpuError> {
    read_texture_layer(ctx, texture, aspect, 0)
}

/// Reads layer `layer` (mip 0) of a 2D texture array and blocks until the copy is done.
pub fn read_texture_layer(
    ctx: &GpuContext,
    texture: &wgpu::Texture,
    aspect: wgpu::TextureAspect,
    layer: u32,
) -> Result<TexelRows, GpuError> {
    if layer >= texture.depth_or_array_layers() {
        return Err(GpuError::Readback {
            what: format!("layer {layer}"),
            reason: format!("the texture has {} layers", texture.depth_or_array_layers()),
        });
    }
    let (width, height) = (texture.width(), texture.height());
    let bytes_per_texel = texture
        .format()
        .block_copy_size(Some(aspect))
        .ok_or_else(|| GpuError::Readback {
            what: format!("{:?}", texture.format()),
            reason: "format cannot be copied to a buffer".into(),
        })?;
    let unpadded = width * bytes_per_texel;
    let padded =
        unpadded.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback::texture"),
        size: u64::from(padded) * u64::from(height),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = ctx
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("readback::texture"),
        });
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d {
                x: 0,
                y: 0,
                z: layer,
            },
            aspect,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(height),
            },
        },
        wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
    );
    ctx.queue.submit([encoder.finish()]);
    let padded_bytes = map_and_copy(ctx, &buffer, "texture")?;
    let mut bytes = Vec::with_capacity((unpadded * height) as usize);
    for row in padded_bytes.chunks(padded as usize) {
        bytes.extend_from_slice(&row[..unpadded as usize]);
    }
    Ok(TexelRows {
        width,
        height,
        bytes_per_texel,
        bytes,
    })
}

/// Reads one texel (mip 0) of a colour texture and blocks; `None` outside the texture. For a
/// user's click, not the frame loop.
pub fn read_texel(
    ctx: &GpuContext,
    texture: &wgpu::Texture,
    x: u32,
    y: u32,
) -> Result<Option<Vec<u8>>, GpuError> {
    if x >= texture.width() || y >= texture.height() {
        return Ok(None);
    }
    let bytes_per_texel = texture.format().block_copy_size(None).unwrap_or(4);
    let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback::texel"),
        size: u64::from(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = ctx
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("readback::texel"),
        });
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d { x, y, z: 0 },
            aspect: wgpu::TextureAspect::All,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT),
                rows_per_image: Some(1),
            },
        },
        wgpu::Extent3d {
            width: 1,
            height: 1,
            depth_or_array_layers: 1,
        },
    );
    ctx.queue.submit([encoder.finish()]);
    let bytes = map_and_copy(ctx, &buffer, "texel")?;
    Ok(Some(bytes[..bytes_per_texel as usize].to_vec()))
}

/// Copies the first `size` bytes of `buffer` (which needs `COPY_SRC`) to the CPU and waits.
/// For tests and reports, never the window loop.
pub fn read_buffer(
    ctx: &GpuContext,
    buffer: &wgpu::Buffer,
    size: u64,
    what: &str,
) -> Result<Vec<u8>, GpuError> {
    let staging = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback::buffer"),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = ctx
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("readback::buffer"),
        });
    encoder.copy_buffer_to_buffer(buffer, 0, &staging, 0, size);
    ctx.queue.submit([encoder.finish()]);
    map_and_copy(ctx, &staging, what)
}

/// Reads `count` `u32` flags from the start of `buffer` as booleans (non-zero is true).
pub fn read_flags(
    ctx: &GpuContext,
    buffer: &wgpu::Buffer,
    count: u32,
    what: &str,
) -> Result<Vec<bool>, GpuError> {
    let bytes = read_buffer(ctx, buffer, u64::from(count.max(1)) * 4, what)?;
    let words: Vec<u32> = bytemuck::pod_collect_to_vec(&bytes);
    Ok(words
        .into_iter()
        .take(count as usize)
        .map(|w| w != 0)
        .collect())
}

/// Maps a `MAP_READ` buffer, waits, and returns its contents.
pub fn map_and_copy(
    ctx: &GpuContext,
    buffer: &wgpu::Buffer,
    what: &str,
) -> Result<Vec<u8>, GpuError> {
    let slice = buffer.slice(..);
    let (sender, receiver) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |result| {
        // The receiver outlives this callback; a failed send only means nobody waits any more.
        let _ = sender.send(result);
    });
    ctx.wait_idle()?;
    let error = |reason: String| GpuError::Readback {
        what: what.to_owned(),
        reason,
    };
    receiver
        .recv()
        .map_err(|e| error(e.to_string()))?
        .map_err(|e| error(e.to_string()))?;
    let bytes = slice
        .get_mapped_range()
        .map_err(|e| error(e.to_string()))?
        .to_vec();
    buffer.unmap();
    Ok(bytes)
}

impl TexelRows {
    /// The texels as `u32` (for `R32Uint` targets).
    pub fn to_u32(&self) -> Vec<u32> {
        bytemuck::pod_collect_to_vec(&self.bytes)
    }

    /// The texels as `f32` (for `R32Float` and `Depth32Float`).
    pub fn to_f32(&self) -> Vec<f32> {
        bytemuck::pod_collect_to_vec(&self.bytes)
    }

    /// An RGBA8 image; `None` unless the texture had 4 bytes per texel.
    pub fn into_rgba_image(self) -> Option<image::RgbaImage> {
        if self.bytes_per_texel != 4 {
            return None;
        }
        image::RgbaImage::from_raw(self.width, self.height, self.bytes)
    }
}
