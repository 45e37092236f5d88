//! Backend `cpu`: single precision on every core (rayon), written to be a fair, strong CPU
//! competitor for the Vulkan engine. No locks and no atomics: each pass computes per-element
//! results in parallel (one spring, one tet), then a per-node pass gathers them through CSR
//! adjacency (node -> spring ends, node -> tet corners). Data is packed in flat arrays of
//! 16-byte SIMD vectors ([`Vec3A`]); parallel loops run in chunks of at least [`CHUNK`].

use glam::Vec3A;
use rayon::prelude::*;

use super::{check_state, diverged, node_tet_corners, Bad};
use crate::backend::{Backend, State, VolumeSample};
use crate::error::Result;
use crate::model::{Csr, Model};
use crate::params::{Method, SimParams};
use crate::physics::{
    distance_constraint, floor_solve, implicit_lambda, integrate_node, spring_force, tet_volume,
    volume_constraint, Vector,
};

/// Smallest number of elements one parallel task handles.
pub const CHUNK: usize = 1024;

/// The parameters of a step, in single precision.
#[derive(Debug, Clone, Copy)]
struct Coefficients {
    dt: f32,
    ks: f32,
    kd: f32,
    friction: f32,
    epsilon: f32,
    gravity: Vec3A,
}

/// The fast CPU solver (`cpu`).
#[derive(Debug, Clone)]
pub struct ParallelBackend {
    method: Method,
    substeps: u32,
    iterations: u32,
    floor: bool,
    k: Coefficients,
    mass: Vec<f32>,
    inv_mass: Vec<f32>,
    springs: Vec<[u32; 2]>,
    rest_length: Vec<f32>,
    tets: Vec<[u32; 4]>,
    rest_volume: Vec<f32>,
    /// node -> `2 * spring + end` (end 0 is `springs[s][0]`).
    node_spring_ends: Csr,
    /// node -> `4 * tet + corner`.
    node_tet_corners: Csr,
    /// Scale of each node's inverse mass in a constraint's `A` (its constraint count for
    /// the momentum-conserving scaling, else 1; `ConstraintCombine::node_factors`).
    a_scale: Vec<f32>,
    /// Factor applied to a node's summed constraint forces: `omega` times the combine
    /// mode's apply weight.
    constraint_scale: Vec<f32>,
    /// The floor's normal force on each node in the current step [N] (`>= 0`).
    floor_force: Vec<f32>,
    x: Vec<Vec3A>,
    v: Vec<Vec3A>,
    /// Total force of the current step [N].
    f: Vec<Vec3A>,
    /// Per-spring result: force on the spring's end 0 (end 1 gets its negation).
    spring_out: Vec<Vec3A>,
    /// Per-tet result: force on each corner.
    tet_out: Vec<[Vec3A; 4]>,
    frame: u32,
    /// Divergence speed limit [m/s] ([`crate::stability::speed_limit`]).
    speed_limit: f32,
    /// The likely cause printed on divergence.
    likely: String,
}

impl ParallelBackend {
    /// A solver at the model's initial positions and velocities. Fails on invalid parameters.
    pub fn new(model: &Model, params: &SimParams) -> Result<Self> {
        params.validate()?;
        let n = model.node_count();
        let ns = &model.node_springs;
        let mut ends = Csr {
            offsets: ns.offsets.clone(),
            items: Vec::with_capacity(ns.items.len()),
        };
        for i in 0..n {
            for &s in ns.row(i) {
                let end = u32::from(model.springs[s as usize][0] as usize != i);
                ends.items.push(2 * s + end);
            }
        }
        let factors: Vec<(f64, f64)> = model
            .constraint_degrees(params.method)
            .unwrap_or_default()
            .into_iter()
            .map(|d| params.combine.node_factors(d))
            .collect();
        let a_scale = factors.iter().map(|f| f.0 as f32).collect();
        let constraint_scale = factors
            .iter()
            .map(|f| (f.1 * params.omega) as f32)
            .collect();
        let to32 = |v: &[f64]| v.iter().map(|&a| a as f32).collect::<Vec<f32>>();
        Ok(ParallelBackend {
            method: params.method,
            substeps: params.substeps,
            iterations: params.iterations,
            floor: params.floor,
            k: Coefficients {
                dt: params.dt as f32,
                ks: params.ks as f32,
                kd: params.kd as f32,
                friction: params.friction as f32,
                epsilon: params.constraint_epsilon as f32,
                gravity: Vec3A::new(0.0, -params.gravity as f32, 0.0),
            },
            mass: to32(&model.mass),
            inv_mass: to32(&model.inv_mass),
            springs: model.springs.clone(),
            rest_length: to32(&model.rest_length),
            tets: model.tets.clone(),
            rest_volume: to32(&model.rest_volume),
            node_spring_ends: ends,
            node_tet_corners: node_tet_corners(model),
            a_scale,
            constraint_scale,
            floor_force: vec![0.0; n],
            x: model
                .positions
                .iter()
                .map(|&p| Vec3A::from_dvec3(p))
                .collect(),
            v: model
                .velocities
                .iter()
                .map(|&v| Vec3A::from_dvec3(v))
                .collect(),
            f: vec![Vec3A::ZERO; n],
            spring_out: vec![Vec3A::ZERO; model.springs.len()],
            tet_out: vec![[Vec3A::ZERO; 4]; model.tets.len()],
            frame: 0,
            speed_limit: crate::stability::speed_limit(model, params) as f32,
            likely: crate::stability::likely_cause(model, params),
        })
    }

    /// Replaces positions and velocities (rounded to f32).
    pub fn set_state(&mut self, state: &State) -> Result<()> {
        check_state(self.x.len(), state)?;
        self.x = state
            .positions
            .iter()
            .map(|&p| Vec3A::from_dvec3(p))
            .collect();
        self.v = state
            .velocities
            .iter()
            .map(|&p| Vec3A::from_dvec3(p))
            .collect();
        Ok(())
    }

    /// Pass `springs`: `F = m g + spring forces`. `mss-node` evaluates each spring at both
    /// ends inside one node-centric gather; every other method evaluates each spring once
    /// and gathers the results.
    fn spring_pass(&mut self) {
        let (x, v, k) = (&self.x, &self.v, self.k);
        let (springs, rest, mass) = (&self.springs, &self.rest_length, &self.mass);
        let ends = &self.node_spring_ends;
        if self.method == Method::MssNode {
            self.f
                .par_iter_mut()
                .enumerate()
                .with_min_len(CHUNK)
                .for_each(|(i, f)| {
                    let mut sum = k.gravity * mass[i];
                    for &e in ends.row(i) {
                        let s = (e >> 1) as usize;
                        let j = springs[s][1 - (e & 1) as usize] as usize;
                        sum += spring_force(x[i], x[j], v[i], v[j], rest[s], k.ks, k.kd);
                    }
                    *f = sum;
                });
            return;
        }
        self.spring_out
            .par_iter_mut()
            .enumerate()
            .with_min_len(CHUNK)
            .for_each(|(s, out)| {
                let [i, j] = springs[s].map(|a| a as usize);
                *out = spring_force(x[i], x[j], v[i], v[j], rest[s], k.ks, k.kd);
            });
        let out = &self.spring_out;
        self.f
            .par_iter_mut()
            .enumerate()
            .with_min_len(CHUNK)
            .for_each(|(i, f)| {
                *f = k.gravity * mass[i] + gather_ends(ends.row(i), out);
            });
    }

    /// One Jacobi sweep of distance constraints, then the per-node gather into `F`.
    fn distance_pass(&mut self) {
        let (x, v, f, w, k) = (&self.x, &self.v, &self.f, &self.inv_mass, self.k);
        let a_scale = &self.a_scale;
        let (springs, rest) = (&self.springs, &self.rest_length);
        self.spring_out
            .par_iter_mut()
            .enumerate()
            .with_min_len(CHUNK)
            .for_each(|(s, out)| {
                let ids = springs[s].map(|a| a as usize);
                let (c, grad) = distance_constraint(x[ids[0]], x[ids[1]], rest[s]);
                let lambda = implicit_lambda(
                    c,
                    &grad,
                    &ids.map(|i| w[i]),
                    &ids.map(|i| a_scale[i]),
                    &ids.map(|i| v[i]),
                    &ids.map(|i| f[i]),
                    k.dt,
                    k.epsilon,
                );
                *out = lambda.map_or(Vec3A::ZERO, |l| grad[0] * -l);
            });
        let (out, ends, scale) = (
            &self.spring_out,
            &self.node_spring_ends,
            &self.constraint_scale,
        );
        let contact = self
            .floor
            .then_some((&self.x, &self.v, &self.inv_mass, self.k.dt));
        self.f
            .par_iter_mut()
            .zip(self.floor_force.par_iter_mut())
            .enumerate()
            .with_min_len(CHUNK)
            .for_each(|(i, (f, n))| {
                *f += gather_ends(ends.row(i), out) * scale[i];
                if let Some((x, v, w, dt)) = contact {
                    (*f, *n) = floor_solve(*f, *n, x[i].y, v[i].y, w[i], dt);
                }
            });
    }

    /// One Jacobi sweep of volume constraints, then the per-node gather into `F`.
    fn volume_pass(&mut self) {
        let (x, v, f, w, k) = (&self.x, &self.v, &self.f, &self.inv_mass, self.k);
        let a_scale = &self.a_scale;
        let (tets, rest) = (&self.tets, &self.rest_volume);
        self.tet_out
            .par_iter_mut()
            .enumerate()
            .with_min_len(CHUNK)
            .for_each(|(t, out)| {
                let ids = tets[t].map(|a| a as usize);
                let (c, grad) = volume_constraint(ids.map(|i| x[i]), rest[t]);
                let lambda = implicit_lambda(
                    c,
                    &grad,
                    &ids.map(|i| w[i]),
                    &ids.map(|i| a_scale[i]),
                    &ids.map(|i| v[i]),
                    &ids.map(|i| f[i]),
                    k.dt,
                    k.epsilon,
                );
                *out = lambda.map_or([Vec3A::ZERO; 4], |l| grad.map(|g| g * -l));
            });
        let (out, corners, scale) = (
            &self.tet_out,
            &self.node_tet_corners,
            &self.constraint_scale,
        );
        let contact = self
            .floor
            .then_some((&self.x, &self.v, &self.inv_mass, self.k.dt));
        self.f
            .par_iter_mut()
            .zip(self.floor_force.par_iter_mut())
            .enumerate()
            .with_min_len(CHUNK)
            .for_each(|(i, (f, n))| {
                let mut sum = Vec3A::ZERO;
                for &e in corners.row(i) {
                    sum += out[(e >> 2) as usize][(e & 3) as usize];
                }
                *f += sum * scale[i];
                if let Some((x, v, w, dt)) = contact {
                    (*f, *n) = floor_solve(*f, *n, x[i].y, v[i].y, w[i], dt);
                }
            });
    }

    /// Pass `integrate`: the floor's final solve, symplectic Euler with floor friction.
    /// Returns the first node that is non-finite or faster than the speed limit.
    fn integrate_pass(&mut self) -> Option<(usize, Bad)> {
        let (w, k) = (&self.inv_mass, self.k);
        let limit2 = self.speed_limit * self.speed_limit;
        let (on, dt) = (self.floor, self.k.dt);
        self.x
            .par_iter_mut()
            .zip(self.v.par_iter_mut())
            .zip(self.f.par_iter_mut().zip(self.floor_force.par_iter_mut()))
            .enumerate()
            .with_min_len(CHUNK)
            .filter_map(|(i, ((x, v), (f, n)))| {
                if on {
                    (*f, *n) = floor_solve(*f, *n, x.y, v.y, w[i], dt);
                }
                let (x1, v1) = integrate_node(*x, *v, *f, w[i], k.dt, *n > 0.0, k.friction);
                (*x, *v) = (x1, v1);
                *n = 0.0;
                if !(x1.is_finite() && v1.is_finite()) {
                    Some((i, Bad::NonFinite))
                } else if v1.length_squared() > limit2 {
                    Some((i, Bad::TooFast(f64::from(v1.length()))))
                } else {
                    None
                }
            })
            .min_by_key(|(i, _)| *i)
    }

    /// One time step (physics.md steps 1-3).
    fn step(&mut self) -> Option<(usize, Bad)> {
        self.spring_pass();
        for _ in 0..self.iterations {
            match self.method {
                Method::Distance => self.distance_pass(),
                Method::Volume => self.volume_pass(),
                Method::Mss | Method::MssNode => break,
            }
        }
        self.integrate_pass()
    }
}

/// Sum over a node's spring ends of the per-spring results (negated for end 1).
#[inline]
fn gather_ends(ends: &[u32], out: &[Vec3A]) -> Vec3A {
    let mut sum = Vec3A::ZERO;
    for &e in ends {
        let value = out[(e >> 1) as usize];
        if e & 1 == 0 {
            sum += value;
        } else {
            sum -= value;
        }
    }
    sum
}

impl Backend for ParallelBackend {
    fn name(&self) -> &'static str {
        "cpu"
    }

    fn step_frame(&mut self) -> Result<()> {
        for substep in 0..self.substeps {
            if let Some((node, bad)) = self.step() {
                return Err(diverged(
                    self.frame,
                    substep,
                    self.method,
                    node as u32,
                    bad,
                    f64::from(self.speed_limit),
                    &self.likely,
                ));
            }
        }
        self.frame += 1;
        Ok(())
    }

    fn volume(&mut self) -> Result<VolumeSample> {
        let x = &self.x;
        let (volume, inverted) = self
            .tets
            .par_iter()
            .with_min_len(CHUNK)
            .map(|t| {
                let v = tet_volume(t.map(|i| x[i as usize]));
                (f64::from(v), u32::from(v <= 0.0))
            })
            .reduce(|| (0.0, 0), |a, b| (a.0 + b.0, a.1 + b.1));
        Ok(VolumeSample { volume, inverted })
    }

    fn state(&mut self) -> Result<State> {
        Ok(State {
            positions: self.x.iter().map(|p| p.to_dvec3()).collect(),
            velocities: self.v.iter().map(|p| p.to_dvec3()).collect(),
        })
    }
}
