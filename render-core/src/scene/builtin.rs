//! The built-in scenes, deterministic from a seed. STUB: replaced by the real generators.

use super::Scene;

/// A built-in scene's name (as in `builtin:NAME`) and what it is.
#[derive(Clone, Copy, Debug)]
pub struct BuiltinScene {
    pub name: &'static str,
    pub description: &'static str,
}

pub const BUILTIN_SCENES: &[BuiltinScene] = &[];

/// The built-in scene `name`, generated from `seed`; `None` for an unknown name.
pub fn load_builtin(_name: &str, _seed: u64) -> Option<Scene> {
    None
}
