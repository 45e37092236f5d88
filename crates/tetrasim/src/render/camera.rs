//! The camera and the scene's frame: where the eye is, how big the floor and its grid are,
//! fitted once to the object's starting bounds (the camera never moves during a run, so the
//! picture shows the object falling), or given by `--camera ex,ey,ez,tx,ty,tz`.

use glam::{DVec3, Mat4, Vec3};

use crate::error::{Error, Result};

/// Vertical field of view [degrees].
pub const FOV_Y_DEG: f32 = 35.0;

/// A perspective camera looking from `eye` at `target` (world units [m], +Y up).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Eye position [m].
    pub eye: Vec3,
    /// The point looked at [m].
    pub target: Vec3,
}

impl std::str::FromStr for Camera {
    type Err = Error;
    /// `ex,ey,ez,tx,ty,tz` in metres.
    fn from_str(s: &str) -> Result<Self> {
        let values: Vec<f32> = s
            .split(',')
            .map(|v| v.trim().parse::<f32>())
            .collect::<std::result::Result<_, _>>()
            .map_err(|e| {
                Error::param("camera", format!("`{s}`: {e}; expected ex,ey,ez,tx,ty,tz"))
            })?;
        let [ex, ey, ez, tx, ty, tz] = values[..] else {
            return Err(Error::param(
                "camera",
                format!(
                    "`{s}` has {} numbers; expected 6: ex,ey,ez,tx,ty,tz",
                    values.len()
                ),
            ));
        };
        let camera = Camera {
            eye: Vec3::new(ex, ey, ez),
            target: Vec3::new(tx, ty, tz),
        };
        if !(camera.eye.is_finite() && camera.target.is_finite()) || camera.eye == camera.target {
            return Err(Error::param(
                "camera",
                format!("`{s}`: the eye and the target must be finite and different"),
            ));
        }
        Ok(camera)
    }
}

/// The fitted scene: camera, floor quad and grid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SceneFrame {
    /// The camera.
    pub camera: Camera,
    /// Centre of the floor quad (y = 0) [m].
    pub floor_centre: Vec3,
    /// Half side of the floor quad [m].
    pub floor_half_extent: f32,
    /// Grid line spacing [m] (1, 2 or 5 times a power of ten).
    pub grid: f32,
    /// Height above the floor over which the object's contact darkening fades [m].
    pub contact_height: f32,
    /// Radius of the fitted scene sphere [m].
    pub radius: f32,
}

impl SceneFrame {
    /// Fits the scene to an object with bounds `lo..hi` resting on or above the floor y = 0:
    /// room for the object to spread sideways by 40 % on impact, seen from the front-right and
    /// above so that its contact with the floor shows. `camera` overrides the fitted one.
    pub fn fit(lo: DVec3, hi: DVec3, aspect: f32, camera: Option<Camera>) -> Self {
        let lo = lo.as_vec3();
        let hi = hi.as_vec3();
        let size = hi - lo;
        let centre_xz = Vec3::new(0.5 * (lo.x + hi.x), 0.0, 0.5 * (lo.z + hi.z));
        let half = 0.7 * size.x.max(size.z).max(1e-6);
        let top = hi.y.max(0.0).max(1e-6);
        let box_lo = Vec3::new(centre_xz.x - half, 0.0, centre_xz.z - half);
        let box_hi = Vec3::new(centre_xz.x + half, top, centre_xz.z + half);
        let centre = 0.5 * (box_lo + box_hi);
        let radius = 0.5 * (box_hi - box_lo).length();
        let camera = camera.unwrap_or_else(|| {
            let (az, el) = (35f32.to_radians(), 22f32.to_radians());
            let dir = Vec3::new(az.sin() * el.cos(), el.sin(), az.cos() * el.cos());
            let half_fov = 0.5 * FOV_Y_DEG.to_radians();
            let half_fov_x = (half_fov.tan() * aspect).atan();
            // The fitted sphere is loose (a box's corners): 0.78 of its distance fills more.
            let distance = 0.78 * radius / half_fov.min(half_fov_x).sin();
            Camera {
                eye: centre + dir * distance,
                target: centre,
            }
        });
        SceneFrame {
            camera,
            floor_centre: centre_xz,
            floor_half_extent: 4.0 * radius,
            grid: nice(radius / 2.5),
            contact_height: 0.08 * size.max_element().max(1e-6),
            radius,
        }
    }

    /// World to clip space for an image of `aspect` = width / height (Vulkan clip space:
    /// depth in [0, 1], image rows downwards).
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        let c = self.camera;
        let distance = (c.eye - c.target).length();
        let reach = distance + 5.0 * self.radius;
        let near = (distance - 5.0 * self.radius)
            .max(0.02 * distance)
            .max(1e-4);
        let up = if (c.eye - c.target).normalize().dot(Vec3::Y).abs() > 0.999 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        let view = Mat4::look_at_rh(c.eye, c.target, up);
        let mut proj =
            Mat4::perspective_rh(FOV_Y_DEG.to_radians(), aspect, near, reach.max(near * 2.0));
        proj.y_axis.y = -proj.y_axis.y;
        proj * view
    }
}

/// The largest of 1, 2, 5 times a power of ten that is at most `x` (x > 0).
fn nice(x: f32) -> f32 {
    let p = 10f32.powf(x.log10().floor());
    [5.0, 2.0, 1.0]
        .into_iter()
        .map(|m| m * p)
        .find(|&v| v <= x * 1.0001)
        .unwrap_or(p)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn camera_parses_six_numbers_and_rejects_others() {
        let c: Camera = "1,2,3, 0,0.5,0".parse().unwrap();
        assert_eq!(c.eye, Vec3::new(1.0, 2.0, 3.0));
        assert_eq!(c.target, Vec3::new(0.0, 0.5, 0.0));
        assert!("1,2,3"
            .parse::<Camera>()
            .unwrap_err()
            .to_string()
            .contains("expected 6"));
        assert!("1,2,x,0,0,0".parse::<Camera>().is_err());
        assert!("1,1,1,1,1,1".parse::<Camera>().is_err());
    }

    #[test]
    fn grid_spacing_is_a_nice_number() {
        assert_eq!(nice(0.27), 0.2);
        assert_eq!(nice(0.6), 0.5);
        assert_eq!(nice(1.0), 1.0);
        assert!((nice(0.013) - 0.01).abs() < 1e-7);
    }

    #[test]
    fn the_fitted_scene_projects_inside_the_image() {
        let lo = DVec3::new(-0.5, 0.1, -0.4);
        let hi = DVec3::new(0.5, 1.1, 0.4);
        let frame = SceneFrame::fit(lo, hi, 4.0 / 3.0, None);
        let m = frame.view_proj(4.0 / 3.0);
        for corner in 0..8 {
            let p = Vec3::new(
                if corner & 1 == 0 { -0.5 } else { 0.5 },
                if corner & 2 == 0 { 0.0 } else { 1.1 },
                if corner & 4 == 0 { -0.4 } else { 0.4 },
            );
            let clip = m * p.extend(1.0);
            let ndc = clip.truncate() / clip.w;
            assert!(clip.w > 0.0, "corner {p} is behind the camera");
            assert!(
                ndc.x.abs() < 0.97 && ndc.y.abs() < 0.97,
                "corner {p} -> {ndc}"
            );
            assert!((0.0..1.0).contains(&ndc.z), "corner {p}: depth {}", ndc.z);
        }
        // Higher points are higher in the image (smaller row, i.e. smaller NDC y).
        let y = |h: f32| {
            let c = m * Vec3::new(0.0, h, 0.0).extend(1.0);
            c.y / c.w
        };
        assert!(y(1.0) < y(0.0));
    }
}
