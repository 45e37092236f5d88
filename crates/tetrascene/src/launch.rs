//! From a [`Scene`] to what a run needs: the meshes loaded, placed, pinned and given their
//! initial velocities, combined into one [`Model`] with the scene's colliders, and the
//! [`SimParams`] shared by all objects. `tetrasim run` goes through here both with
//! `--scene FILE` and with flags (which build a one-object scene), so there is one path.

use glam::DVec3;

use crate::scene::{Pins, Scene};
use tetrasim::collider::Clamp;
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
            .rotation(scene.rotation_for(i)?)
            .offset(DVec3::from(object.offset))
            .velocity(DVec3::from(object.velocity))
            .self_contact(object.self_contact);
        for pin in &object.pin.pins {
            builder = builder.pinned(pin.nodes.iter().copied());
            if let Some(b) = pin.region {
                builder = builder.pinned_in_box(DVec3::from(b.min), DVec3::from(b.max));
            }
        }
        let mut model = builder.build().map_err(|e| match e {
            Error::Mesh(m) => Error::Mesh(format!("object[{i}] ({}): {m}", loaded.label)),
            Error::Param { key, message } => Error::param(format!("object[{i}].{key}"), message),
            other => other,
        })?;
        model.clamps = clamps(&object.pin, i, &model)?;
        models.push(model);
        labels.push(loaded.label);
        notes.extend(loaded.note);
    }
    // Each collider was checked with its scene key by `Scene::colliders`.
    let mut model = Model::concat(&models)?.with_colliders(colliders)?;
    for (k, grab) in scene.grabs.iter().enumerate() {
        model = model.with_grab(grab.grab(&format!("grab[{k}]"))?)?;
    }
    Ok(Staged {
        model,
        params,
        frames: scene.frames(),
        label: labels.join("+"),
        notes,
    })
}

/// The clamps of object `object`'s pins on its built `model`: each moving pin holds its
/// `nodes` and the nodes in its `box` (those with mass, as [`ModelBuilder::pin_motion`]
/// holds them) and moves them rigidly about their centroid. A scene may give an object
/// several pins, each with its own motion, which one `pin_motion` cannot express, so the
/// clamps are made here; errors name the pin (`object[0].pin[1].motion`): a moving pin that
/// holds no node, or one that shares a node with another pin.
fn clamps(pins: &Pins, object: usize, model: &Model) -> Result<Vec<Clamp>> {
    if pins.pins.iter().all(|p| p.motion.is_none()) {
        return Ok(Vec::new());
    }
    let held: Vec<Vec<u32>> = pins
        .pins
        .iter()
        .map(|pin| {
            let by_index: std::collections::HashSet<u32> = pin.nodes.iter().copied().collect();
            (0..model.node_count() as u32)
                .filter(|&n| {
                    let p = model.positions[n as usize];
                    by_index.contains(&n) || pin.region.is_some_and(|b| b.contains(p))
                })
                .filter(|&n| model.mass[n as usize] > 0.0)
                .collect()
        })
        .collect();
    let mut out = Vec::new();
    for (j, pin) in pins.pins.iter().enumerate() {
        let key = format!("{}.motion", pins.key(object, j));
        let motion = match &pin.motion {
            Some(spec) => spec.motion(&key)?,
            None => continue,
        };
        if !motion.is_moving() {
            continue;
        }
        let nodes = &held[j];
        if nodes.is_empty() {
            return Err(Error::param(
                key,
                "moves no node: the pin holds none (give `nodes` or a `box` that contains \
                 nodes)",
            ));
        }
        if let Some((k, n)) = held
            .iter()
            .enumerate()
            .filter(|&(k, _)| k != j)
            .find_map(|(k, other)| nodes.iter().find(|n| other.contains(n)).map(|&n| (k, n)))
        {
            return Err(Error::param(
                key,
                format!(
                    "moves node {n}, which {} holds too: a node follows one pin",
                    pins.key(object, k)
                ),
            ));
        }
        out.push(Clamp {
            centre: nodes
                .iter()
                .map(|&n| model.positions[n as usize])
                .sum::<DVec3>()
                / nodes.len() as f64,
            nodes: nodes.clone(),
            motion,
        });
    }
    Ok(out)
}
