//! From a [`Scene`] to what a run needs: the meshes loaded, placed, pinned and given their
//! initial velocities, combined into one [`Model`] with the scene's colliders, and the
//! [`SimParams`] shared by all objects. `tetrasim run` goes through here both with
//! `--scene FILE` and with flags (which build a one-object scene), so there is one path.

use glam::DVec3;

use crate::scene::Scene;
use tetrasim::error::{Error, Result};
use tetrasim::model::{Model, ModelBuilder};
use tetrasim::params::SimParams;
use tetrasim::sim::load_mesh;

/// A scene made ready to run.
#[derive(Debug, Clone)]
pub struct Staged {
    /// All objects as one model (object `k`'s nodes follow those of objects `0..k`).
    pub model: Model,
    /// The solver parameters (every object has the same, see [`stage`]).
    pub params: SimParams,
    /// Frames to simulate.
    pub frames: u32,
    /// Mesh labels joined with `+`, for the record.
    pub label: String,
    /// Remarks of the mesh loader (e.g. meshing settings).
    pub notes: Vec<String>,
}

/// Loads every object of `scene` and combines them, with the scene's colliders
/// ([`Scene::colliders`], read first so that a bad collider fails before any meshing). Objects may differ in material (each
/// model carries its own, [`ModelBuilder::material`]) but must share everything else (one
/// [`SimParams`] drives the engine); a scene mixing methods is an error naming the first
/// object that differs (not supported yet).
pub fn stage(scene: &Scene) -> Result<Staged> {
    let params = scene.params_for(0);
    for i in 1..scene.objects.len() {
        let other = scene.params_for(i);
        let same_material = SimParams {
            ks: params.ks,
            kd: params.kd,
            mass: params.mass,
            youngs_modulus: params.youngs_modulus,
            poisson_ratio: params.poisson_ratio,
            damping: params.damping,
            ..other.clone()
        };
        if same_material != params {
            return Err(Error::param(
                format!("object[{i}]"),
                format!(
                    "has method {}, object[0] has {}: objects with different methods in one \
                     scene are not supported yet",
                    other.method, params.method
                ),
            ));
        }
    }
    let colliders = scene.colliders()?;
    let mut models = Vec::with_capacity(scene.objects.len());
    let mut labels = Vec::new();
    let mut notes = Vec::new();
    for (i, object) in scene.objects.iter().enumerate() {
        let loaded = load_mesh(&object.mesh, object.target_tets).map_err(|e| match e {
            Error::Param { key, message } if scene.objects.len() > 1 => {
                Error::param(format!("object[{i}].{key}"), message)
            }
            other => other,
        })?;
        let mut builder = ModelBuilder::new(&loaded.mesh)
            .placement(scene.placement_for(i))
            .material(&scene.params_for(i))
            .offset(DVec3::from(object.offset))
            .pinned(object.pin.nodes.iter().copied())
            .velocity(DVec3::from(object.velocity));
        if let Some(b) = object.pin.region {
            builder = builder.pinned_in_box(DVec3::from(b.min), DVec3::from(b.max));
        }
        let model = builder.build().map_err(|e| match e {
            Error::Mesh(m) => Error::Mesh(format!("object[{i}] ({}): {m}", loaded.label)),
            Error::Param { key, message } => Error::param(format!("object[{i}].{key}"), message),
            other => other,
        })?;
        models.push(model);
        labels.push(loaded.label);
        notes.extend(loaded.note);
    }
    Ok(Staged {
        // Each collider was checked with its scene key by `Scene::colliders`.
        model: Model::concat(&models)?.with_colliders(colliders)?,
        params,
        frames: scene.frames(),
        label: labels.join("+"),
        notes,
    })
}
