//! The headless GPU tier: known-answer tests of whole frames on the adapter wgpu finds
//! (lavapipe on a machine without a GPU), one module per subject in one test binary, so
//! that the suite links once and its tests share one device and its compiled pipelines.

mod box_clamp;
mod cascades;
mod check_cases;
mod culling;
mod faults;
mod flicker;
mod footprints;
mod fragment_mask;
mod frame;
mod layered;
mod lights_culling;
mod lispsm;
mod measure;
mod observer;
mod packed_gltf;
mod point_volumes;
mod resolution;
mod shadows;
mod truth;
mod views;
mod virtual_allocation;
mod virtual_grid;
mod virtual_maps;
mod virtual_oracle;
mod virtual_point;
mod virtual_receiver_mask;
mod virtual_spot;
mod virtual_static_apart;
mod virtual_static_occlusion;
mod volume_strips;
mod volumes;
