//! What is drawn over the picture to explain it: the light's view inset (a shadow view's map,
//! its mask, the casters the method culled), the observer camera's lines and the colours of caster outcomes that the
//! camera's `casters` tint shares with it. Their colours are `crate::palette`'s. The error heat map is a measure's picture and
//! lives in `metrics/`.

pub(crate) mod light_inset;
pub(crate) mod observer;

pub use light_inset::{LIGHT_VIEW_SIZE, LightInset};
pub use observer::{ObserverLines, observer_segments};
