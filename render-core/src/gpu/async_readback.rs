//! Buffer readback that never blocks: a few staging buffers used in turn. A frame copies into a
//! free one, mapping starts after submit, and a later frame takes whatever has arrived.

use std::sync::{Arc, Mutex};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum SlotState {
    Free,
    Copied,
    Mapping,
    Mapped,
    Failed,
}

struct Slot {
    buffer: wgpu::Buffer,
    state: Arc<Mutex<SlotState>>,
    tag: u64,
}

/// A ring of staging buffers of one size. Long-lived.
pub struct AsyncReadback {
    slots: Vec<Slot>,
    size: u64,
}

impl AsyncReadback {
    pub fn new(device: &wgpu::Device, label: &str, size: u64, slot_count: usize) -> Self {
        let slots = (0..slot_count.max(1))
            .map(|_| Slot {
                buffer: device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size,
                    usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                }),
                state: Arc::new(Mutex::new(SlotState::Free)),
                tag: 0,
            })
            .collect();
        Self { slots, size }
    }

    /// Records a copy of `source` (at least `size` bytes) into a free slot, remembering `tag`.
    /// Returns false when every slot is still in flight; the caller then skips this readback.
    pub fn copy(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        source: &wgpu::Buffer,
        tag: u64,
    ) -> bool {
        let Some(slot) = self.slots.iter_mut().find(|s| state(s) == SlotState::Free) else {
            return false;
        };
        encoder.copy_buffer_to_buffer(source, 0, &slot.buffer, 0, self.size);
        slot.tag = tag;
        set_state(slot, SlotState::Copied);
        true
    }

    /// Starts mapping the slots copied into since the last call; call right after submit.
    pub fn map_copied(&mut self) {
        for slot in self.slots.iter().filter(|s| state(s) == SlotState::Copied) {
            set_state(slot, SlotState::Mapping);
            let state = Arc::clone(&slot.state);
            slot.buffer
                .slice(..)
                .map_async(wgpu::MapMode::Read, move |result| {
                    if let Ok(mut s) = state.lock() {
                        *s = if result.is_ok() {
                            SlotState::Mapped
                        } else {
                            SlotState::Failed
                        };
                    }
                });
        }
    }

    /// The newest arrived copy and its tag; frees every arrived slot. Needs a device poll first.
    pub fn take_latest(&mut self) -> Option<(u64, Vec<u8>)> {
        let mut latest: Option<(u64, Vec<u8>)> = None;
        for slot in &mut self.slots {
            match state(slot) {
                SlotState::Mapped => {
                    let bytes = slot
                        .buffer
                        .slice(..)
                        .get_mapped_range()
                        .ok()
                        .map(|view| view.to_vec());
                    slot.buffer.unmap();
                    set_state(slot, SlotState::Free);
                    if let Some(bytes) = bytes
                        && latest.as_ref().is_none_or(|(tag, _)| *tag < slot.tag)
                    {
                        latest = Some((slot.tag, bytes));
                    }
                }
                SlotState::Failed => set_state(slot, SlotState::Free),
                _ => {}
            }
        }
        latest
    }
}

fn state(slot: &Slot) -> SlotState {
    slot.state.lock().map_or(SlotState::Failed, |s| *s)
}

fn set_state(slot: &Slot, new: SlotState) {
    if let Ok(mut s) = slot.state.lock() {
        *s = new;
    }
}
