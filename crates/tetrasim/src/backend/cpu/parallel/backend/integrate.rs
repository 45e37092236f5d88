//! The `integrate` pass of the `cpu` backend.

use super::*;

impl ParallelBackend {
    /// Stage `integrate` (`solve` full) or `split_velocity` (split contact's velocity
    /// solve): the floor's and the colliders' final solve, symplectic Euler with floor and
    /// collider friction, then `F = m g` for the next solve. `integrate` moves the nodes
    /// (with split contact, to the velocity solve's velocities), `split_velocity` keeps the
    /// new velocities aside. Returns the first node that is non-finite or faster than the
    /// speed limit.
    pub(super) fn integrate_pass(
        &mut self,
        at: &[ColliderAt<'_>],
        solve: Solve,
    ) -> Option<(usize, Bad)> {
        let (w, k, mass) = (&self.inv_mass, self.k, &self.mass);
        let limit2 = self.speed_limit * self.speed_limit;
        let (on, dt) = (self.floor, self.k.dt);
        let (clearance, attached) = (&self.clearance, &self.attached);
        let pushed = std::sync::atomic::AtomicU32::new(0);
        let split = !self.split_v.is_empty();
        let split_v = SharedSlice::new(&mut self.split_v);
        let warm = self.elastic_warm;
        let full = solve == Solve::Full;
        let held = SharedSlice::new(&mut self.supports.held);
        let pushed_by = SharedSlice::new(&mut self.supports.pushed);
        let floor_kept = SharedSlice::new(&mut self.supports.floor);
        let bad = self
            .x
            .par_iter_mut()
            .zip(self.v.par_iter_mut())
            .zip(self.f.par_iter_mut().zip(self.floor_force.par_iter_mut()))
            .enumerate()
            .with_min_len(CHUNK)
            .zip(self.contact.par_iter_mut())
            .filter_map(|((i, ((x, v), (f, n))), c)| {
                if on {
                    (*f, *n) = floor_solve(*f, *n, x.y + solve.slack(x.y), v.y, w[i], dt);
                }
                let touch = match at.is_empty() && attached.is_empty() {
                    true => None,
                    false => {
                        let held = attached.get(i).copied().flatten();
                        let touch = collide(at, clearance[i], held, solve, f, c, *x, *v, w[i], dt);
                        *c = Vec3A::ZERO;
                        if touch.touching.is_some() {
                            pushed.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                        }
                        touch.touching.is_some().then_some(touch)
                    }
                };
                // The supports' share of the forces out (the full solve's).
                if full {
                    // SAFETY: each node's entries are written by its own iteration only.
                    unsafe {
                        if w[i] <= 0.0 && !held.is_empty() {
                            held.part(i..i + 1)[0] = *f;
                        }
                        if !pushed_by.is_empty() {
                            pushed_by.part(i..i + 1)[0] = match &touch {
                                Some(t) => (
                                    t.touching.map_or(u32::MAX, |t| t.collider as u32),
                                    Vec3A::from_dvec3(t.force),
                                ),
                                None => (u32::MAX, Vec3A::ZERO),
                            };
                        }
                        if !floor_kept.is_empty() {
                            floor_kept.part(i..i + 1)[0] = *n;
                        }
                    }
                }
                // Finite elements start the next step where this one's fall (its total
                // force after the floor and the colliders) takes them.
                let elastic = match warm {
                    true => elastic_start(*f, mass[i], k.gravity),
                    false => Vec3A::ZERO,
                };
                let (mut x1, mut v1) = integrate_node(*x, *v, *f, w[i], k.dt, *n, k.friction);
                if let Some(touch) = touch {
                    let v2 = collider::friction_of(
                        at,
                        &touch,
                        x.to_dvec3(),
                        v1.to_dvec3(),
                        f64::from(dt),
                    );
                    v1 = Vec3A::from_dvec3(v2);
                    x1 = *x + v1 * dt;
                }
                *n = 0.0;
                *f = k.gravity * mass[i] + elastic;
                if split {
                    // SAFETY: each node's entry is written or read by its own iteration only.
                    let kept = unsafe { &mut split_v.part(i..i + 1)[0] };
                    match solve {
                        Solve::Velocity => {
                            *kept = v1;
                            x1 = *x;
                        }
                        Solve::Full => v1 = *kept,
                    }
                }
                if solve == Solve::Full {
                    (*x, *v) = (x1, v1);
                }
                if !(x1.is_finite() && v1.is_finite()) {
                    Some((i, Bad::NonFinite))
                } else if v1.length_squared() > limit2 {
                    Some((i, Bad::TooFast(f64::from(v1.length()))))
                } else {
                    None
                }
            })
            .min_by_key(|(i, _)| *i);
        if solve == Solve::Full {
            self.pushed = pushed.into_inner();
        }
        bad
    }
}
