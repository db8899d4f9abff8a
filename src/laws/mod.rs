//! Contact laws with history (models.md): model configuration, history transport, the
//! spring-dashpot-slider step, the per-contact step, and the time-step helpers.

pub mod checked;
pub mod fast_path;
pub mod materials;
pub mod model;
pub mod presets;
pub mod spring;
pub mod stability;
pub mod step;
pub mod swap;
pub mod transport;
