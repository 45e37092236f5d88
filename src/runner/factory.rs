//! The one place where backend names become backends. A new backend adds one match arm here
//! and one entry to [`BACKENDS`].

use crate::backend::Backend;
use crate::cpu::{ParallelBackend, ReferenceBackend};
use crate::engine::{EngineOptions, VulkanBackend};
use crate::error::{Error, Result};
use crate::model::Model;
use crate::params::SimParams;

/// Names accepted by [`create_backend`] (and by `--backend`).
pub const BACKENDS: [&str; 3] = ["cpu-ref", "cpu", "vulkan"];

/// Creates the backend called `name` for `model` with `params`, at the model's initial
/// positions and at rest.
pub fn create_backend(name: &str, model: &Model, params: &SimParams) -> Result<Box<dyn Backend>> {
    create_backend_with(name, model, params, &EngineOptions::default())
}

/// [`create_backend`] with the `vulkan` backend's device, validation and workgroup options.
pub fn create_backend_with(
    name: &str,
    model: &Model,
    params: &SimParams,
    gpu: &EngineOptions,
) -> Result<Box<dyn Backend>> {
    match name {
        "vulkan" => Ok(Box::new(VulkanBackend::new(model, params, gpu)?)),
        "cpu-ref" => Ok(Box::new(ReferenceBackend::new(model, params)?)),
        "cpu" => Ok(Box::new(ParallelBackend::new(model, params)?)),
        other => Err(Error::param(
            "backend",
            format!(
                "unknown backend `{other}`; known backends: {}",
                BACKENDS.join(", ")
            ),
        )),
    }
}
