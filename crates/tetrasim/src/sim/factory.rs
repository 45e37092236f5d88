//! The one place where backend names become backends. A new backend adds one match arm here
//! and one entry to [`BACKENDS`]. [`BackendFactory`] keeps one Vulkan context for every
//! `vulkan` backend it creates (one instance and device for a whole benchmark).

use std::sync::Arc;

use crate::backend::cpu::{memory, ParallelBackend, ReferenceBackend};
use crate::backend::vulkan::{EngineOptions, VulkanBackend};
use crate::backend::Backend;
use crate::error::{Error, Result};
use crate::gpu::{Context, ContextOptions};
use crate::model::Model;
use crate::params::SimParams;
use crate::problem::Problem;

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
    BackendFactory::new(gpu.clone()).create(name, &Problem::new(model, params)?)
}

/// Creates backends by name; every `vulkan` backend it makes shares one Vulkan context,
/// created on first use.
pub struct BackendFactory {
    gpu: EngineOptions,
    ctx: Option<Arc<Context>>,
}

impl BackendFactory {
    /// A factory whose `vulkan` backends get these options (device, validation, workgroup
    /// size, timing, volume read-back).
    pub fn new(gpu: EngineOptions) -> Self {
        BackendFactory { gpu, ctx: None }
    }

    /// The options `vulkan` backends get.
    pub fn options(&self) -> &EngineOptions {
        &self.gpu
    }

    /// The backend `name` for a prepared problem, at its model's initial state.
    pub fn create(&mut self, name: &str, problem: &Problem) -> Result<Box<dyn Backend>> {
        let gpu = self.gpu.clone();
        self.create_with(name, problem, &gpu)
    }

    /// [`BackendFactory::create`] with other `vulkan` options (the device and validation
    /// stay the factory's: the context is shared).
    pub fn create_with(
        &mut self,
        name: &str,
        problem: &Problem,
        gpu: &EngineOptions,
    ) -> Result<Box<dyn Backend>> {
        match name {
            "vulkan" => Ok(Box::new(self.vulkan(problem, gpu)?)),
            "cpu-ref" => {
                memory::check(name, problem, gpu.memory_limit)?;
                Ok(Box::new(ReferenceBackend::from_problem(problem)))
            }
            "cpu" => {
                memory::check(name, problem, gpu.memory_limit)?;
                Ok(Box::new(ParallelBackend::from_problem(problem)))
            }
            other => Err(Error::param(
                "backend",
                format!(
                    "unknown backend `{other}`; known backends: {}",
                    BACKENDS.join(", ")
                ),
            )),
        }
    }

    /// A `vulkan` backend on the shared context.
    pub fn vulkan(&mut self, problem: &Problem, gpu: &EngineOptions) -> Result<VulkanBackend> {
        let ctx = match &self.ctx {
            Some(ctx) => ctx.clone(),
            None => {
                let ctx = Context::shared(&ContextOptions {
                    device: self.gpu.device.clone(),
                    validation: self.gpu.validation,
                })?;
                self.ctx = Some(ctx.clone());
                ctx
            }
        };
        VulkanBackend::on_context(ctx, problem, gpu)
    }
}
