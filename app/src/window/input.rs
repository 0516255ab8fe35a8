//! Mouse and keyboard: winit's window events routed to egui and the camera (the panel's
//! shortcuts are `ui::shortcuts`, read from egui's input), and a click on the 3D view that picks
//! the object under the cursor.

use glam::Vec2;
use render_core::gpu::read_texel;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::ActiveEventLoop;
use winit::keyboard::{KeyCode, PhysicalKey};

use super::Running;
use super::camera_control::Drag;

impl Running {
    pub(super) fn on_window_event(&mut self, event_loop: &ActiveEventLoop, event: &WindowEvent) {
        let response = self.egui_state.on_window_event(&self.window, event);
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => self.surface.resize(&self.ctx, size.width, size.height),
            WindowEvent::DroppedFile(path) => self.open_scene(&path.display().to_string()),
            WindowEvent::RedrawRequested => self.redraw(event_loop),
            WindowEvent::ModifiersChanged(m) => {
                self.alt_held = m.state().alt_key();
                self.keys.fast = m.state().shift_key();
            }
            WindowEvent::KeyboardInput { event: key, .. } if !self.egui_ctx.text_edit_focused() => {
                if let PhysicalKey::Code(code) = key.physical_key {
                    self.on_key(code, key.state == ElementState::Pressed);
                }
            }
            WindowEvent::MouseInput { state, button, .. } => {
                self.on_mouse_button(*button, *state == ElementState::Pressed, response.consumed);
            }
            WindowEvent::CursorMoved { position, .. } => {
                let now = Vec2::new(position.x as f32, position.y as f32);
                if let Some(before) = self.cursor_px {
                    self.controller.on_mouse_drag(now - before);
                }
                self.cursor_px = Some(now);
            }
            WindowEvent::CursorLeft { .. } => self.cursor_px = None,
            WindowEvent::MouseWheel { delta, .. } if self.cursor_over_view() => {
                let notches = match delta {
                    MouseScrollDelta::LineDelta(_, y) => *y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 50.0,
                };
                self.controller.on_wheel(notches);
            }
            _ => {}
        }
    }

    fn on_key(&mut self, code: KeyCode, pressed: bool) {
        match code {
            KeyCode::KeyW => self.keys.forward = pressed,
            KeyCode::KeyS => self.keys.back = pressed,
            KeyCode::KeyA => self.keys.left = pressed,
            KeyCode::KeyD => self.keys.right = pressed,
            KeyCode::KeyE => self.keys.up = pressed,
            KeyCode::KeyQ => self.keys.down = pressed,
            KeyCode::Escape if pressed => self.controller.drag = Drag::None,
            _ => {}
        }
    }

    fn on_mouse_button(&mut self, button: MouseButton, pressed: bool, egui_consumed: bool) {
        if !pressed {
            self.controller.drag = Drag::None;
            // A left click that did not move selects the object under the cursor.
            if let (MouseButton::Left, Some(start), Some(now)) =
                (button, self.click_start.take(), self.cursor_px)
                && (now - start).length() < 4.0
            {
                self.select_at(now);
            }
            return;
        }
        if egui_consumed || !self.cursor_over_view() {
            return;
        }
        if button == MouseButton::Left && !self.alt_held {
            self.click_start = self.cursor_px;
        }
        self.controller.drag = match button {
            MouseButton::Right => Drag::Fly,
            MouseButton::Middle => Drag::Orbit,
            MouseButton::Left if self.alt_held => Drag::Orbit,
            _ => self.controller.drag,
        };
    }

    /// Reads the object id under `cursor_px` (window pixels) and remembers that object, or
    /// clears the selection on sky. Blocks for a one-texel readback: a click, not a frame.
    fn select_at(&mut self, cursor_px: Vec2) {
        let Some(targets) = self.renderer.targets() else {
            return;
        };
        let ppp = self.egui_ctx.pixels_per_point();
        let x = cursor_px.x - self.view_rect.min.x * ppp;
        let y = cursor_px.y - self.view_rect.min.y * ppp;
        if x < 0.0 || y < 0.0 {
            return;
        }
        match read_texel(&self.ctx, &targets.ids, x as u32, y as u32) {
            Ok(Some(bytes)) => {
                let id = u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]);
                self.selected = id.checked_sub(1).map(|instance| {
                    let oracle = self
                        .settings
                        .measure
                        .then(|| self.renderer.read_oracle(&self.ctx, &self.scene_gpu).ok())
                        .flatten()
                        .and_then(|flags| flags.get(instance as usize).copied());
                    let volume_intervals = self
                        .renderer
                        .read_volume_intervals(&self.ctx, instance)
                        .unwrap_or_else(|e| {
                            self.message =
                                Some(format!("Could not read the volume's intervals: {e}"));
                            None
                        });
                    Selected {
                        instance,
                        oracle,
                        volume_intervals,
                    }
                });
            }
            Ok(None) => {}
            Err(e) => {
                self.message = Some(format!("Could not read the object under the cursor: {e}"));
            }
        }
    }

    /// The selected object as the panel shows it, from the last frame's outcome.
    pub(super) fn selection(&self) -> Option<ui::Selection> {
        let Selected {
            instance,
            oracle,
            volume_intervals,
        } = self.selected.clone()?;
        let inst = self.scene.instances.get(instance as usize)?;
        let stages = self
            .last_report
            .as_ref()
            .map_or(&[][..], |r| r.stages.as_slice());
        let outcome = self
            .renderer
            .caster_outcomes()
            .get(instance as usize)
            .copied()?;
        Some(ui::Selection {
            name: inst.name.clone(),
            casts_shadow: inst.casts_shadow,
            receives_shadow: inst.receives_shadow,
            visible: true,
            shadow_map: outcome.describe(stages),
            oracle,
            volume_intervals,
        })
    }

    fn cursor_over_view(&self) -> bool {
        let ppp = self.egui_ctx.pixels_per_point();
        self.cursor_px
            .is_some_and(|p| self.view_rect.contains(egui::pos2(p.x / ppp, p.y / ppp)))
    }
}

/// The clicked instance and what was read about it at the click: whether it was in the
/// oracle set (when measuring) and its shadow volume's intervals (with shadow volumes).
#[derive(Clone, Debug)]
pub(super) struct Selected {
    pub instance: u32,
    pub oracle: Option<bool>,
    pub volume_intervals: Option<Vec<[f32; 2]>>,
}
