//! GPU faults a frame survives (`render-core/src/gpu/faults.rs`): memory the device cannot
//! give and a lost device come back as typed errors that name them, never as a wgpu panic, and
//! a renderer whose frame ran out of memory draws its earlier settings as it drew them before.
//! Each test opens a device of its own: a fault belongs to its device, and the shared one
//! must not see another test's.

use glam::Vec3;
use render_core::frame::{
    FrameCapture, FrameInput, FrameRenderer, FrameSettings, Method, ShadowSetup,
};
use render_core::geom::Camera;
use render_core::gpu::{GpuContext, GpuError, GpuFault};
use render_core::scene::{Scene, load_builtin};
use render_core::scene_gpu::SceneGpu;
use render_core::shadow_view::LayeredPath;

const SIZE: (u32, u32) = (160, 120);

fn own_device() -> GpuContext {
    GpuContext::headless().expect("an adapter")
}

fn camera() -> Camera {
    Camera::look_at(
        Vec3::new(-14.0, 9.0, 16.0),
        Vec3::new(0.0, 2.0, 0.0),
        60f32.to_radians(),
        0.1,
        200.0,
    )
}

/// The hall's lights, each with a map `resolution` texels square, drawn into one atlas.
fn lights_at(resolution: u32) -> FrameSettings {
    let mut settings = FrameSettings {
        setup: ShadowSetup::Lights,
        method: Method::Vfc,
        ..FrameSettings::default()
    };
    settings.shadow.resolution = resolution;
    settings.layered.path = LayeredPath::Traditional;
    settings
}

fn frame(
    ctx: &GpuContext,
    renderer: &mut FrameRenderer,
    (scene, scene_gpu): (&Scene, &SceneGpu),
    settings: &FrameSettings,
) -> Result<FrameCapture, GpuError> {
    let camera = camera();
    let input = FrameInput {
        camera: &camera,
        width: SIZE.0,
        height: SIZE.1,
        settings,
    };
    renderer.render_and_wait(ctx, scene, scene_gpu, &input)?;
    FrameCapture::read(ctx, renderer.targets().expect("a frame drew"))
}

#[test]
fn maps_the_gpu_cannot_hold_are_a_fault_naming_them_and_the_earlier_settings_draw_as_before() {
    let ctx = own_device();
    let scene = load_builtin("hall", 0).expect("hall");
    let scene_gpu = SceneGpu::new(&ctx, &scene);
    let mut renderer = FrameRenderer::new(&ctx);
    let pair = (&scene, &scene_gpu);
    let before = frame(&ctx, &mut renderer, pair, &lights_at(256)).expect("256 fits");
    let layers = renderer.last_views().len() as u64;
    assert!(
        layers >= 32,
        "the hall's 32 lights, a map or six each: {layers}"
    );

    // 4.5 GiB of maps: lavapipe refuses one allocation that large. Asked twice, the same
    // answer: the renderer does not keep the texture that failed.
    for _ in 0..2 {
        out_of_memory(
            &ctx,
            frame(&ctx, &mut renderer, pair, &lights_at(4096)),
            layers,
        );
    }
    // The fault was taken: the settings before draw again, and as before.
    let again = frame(&ctx, &mut renderer, pair, &lights_at(256)).expect("256 fits again");
    let differ = before
        .color
        .pixels()
        .zip(again.color.pixels())
        .filter(|(a, b)| a != b)
        .count();
    assert_eq!(differ, 0, "pixels differ after the fault");
    assert_eq!(before.shadow, again.shadow);
}

/// Checks that `result` is the lights' maps' memory, on lavapipe; a GPU with 4.5 GiB to give
/// in one texture may have drawn.
fn out_of_memory(ctx: &GpuContext, result: Result<FrameCapture, GpuError>, layers: u64) {
    match result {
        Err(GpuError::Fault(GpuFault::OutOfMemory {
            what,
            asked,
            remedy,
        })) => {
            assert_eq!(asked, layers * 4096 * 4096 * 4, "{what}");
            assert!(
                what.contains(&format!("{layers} layers of 4096 x 4096")),
                "{what}"
            );
            assert!(remedy.contains("--shadow-res"), "{remedy}");
        }
        Err(other) => panic!("not the maps' memory: {other}"),
        Ok(_) => {
            // An adapter with that much memory to give (a large GPU) has nothing to refuse.
            let info = ctx.adapter.get_info();
            assert_ne!(
                info.device_type,
                wgpu::DeviceType::Cpu,
                "{} gave 4.5 GiB in one texture",
                info.name
            );
        }
    }
}

#[test]
fn a_lost_device_is_a_fault_naming_it_in_every_frame_after() {
    let ctx = own_device();
    let scene = load_builtin("boxes", 0).expect("boxes");
    let scene_gpu = SceneGpu::new(&ctx, &scene);
    let mut renderer = FrameRenderer::new(&ctx);
    let pair = (&scene, &scene_gpu);
    let settings = FrameSettings::default();
    frame(&ctx, &mut renderer, pair, &settings).expect("a frame before the loss");
    ctx.device.destroy();
    for attempt in 0..2 {
        match frame(&ctx, &mut renderer, pair, &settings) {
            Err(GpuError::Fault(fault @ GpuFault::DeviceLost { .. })) => {
                assert!(
                    fault.to_string().starts_with("the GPU device was lost"),
                    "{fault}"
                );
            }
            Err(other) => panic!("frame {attempt} after the loss: not the loss: {other}"),
            Ok(_) => panic!("frame {attempt} after the loss drew"),
        }
    }
}
