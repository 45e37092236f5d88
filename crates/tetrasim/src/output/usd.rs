//! An animated USD stage (`.usda`, USD's text form) of a run: each body's boundary surface
//! as a `Mesh` prim under `/World` with its points time-sampled at the frames written and
//! each vertex's volume ratio (V/V0 of the node's tets) as the `vertex` primvar
//! `volume_ratio`; metres (`metersPerUnit = 1`), up axis +Y (the floor `y = 0`), one time
//! code per frame and `timeCodesPerSecond` the frames per simulated second, so a player
//! shows the motion in real time. Blender, Houdini, Omniverse and usdview open it as an
//! animation. The stage is kept in memory (as the text of its samples) and written once,
//! through a temporary file and a rename, by [`UsdSeries::write`].

use std::fmt::Write as _;
use std::path::Path;

use super::{surface_of, FrameData, OutputUnits};
use crate::backend::State;
use crate::error::Result;
use crate::mesh::io;
use crate::model::Model;

/// One body's prim: its surface's nodes and triangles, and the text of its samples so far.
#[derive(Debug, Clone)]
struct UsdBody {
    nodes: Vec<usize>,
    triangles: Vec<[u32; 3]>,
    points: String,
    ratios: String,
}

/// The frames of a run as one USD stage ([module docs](self)).
#[derive(Debug, Clone)]
pub struct UsdSeries {
    bodies: Vec<UsdBody>,
    frame_time: f64,
    frames: Vec<u32>,
    doc: String,
}

impl UsdSeries {
    /// A stage of `model`'s bodies (one prim per object, `/World/body_K`), frames
    /// `frame_time` [s] apart; `doc` becomes the stage's documentation string.
    pub fn new(model: &Model, frame_time: f64, doc: &str) -> Self {
        let positions = &model.positions;
        let bodies = (model.objects.windows(2))
            .map(|range| {
                let (lo, hi) = (range[0], range[1]);
                let faces: Vec<[u32; 3]> = (model.surface.iter())
                    .filter(|f| f.iter().all(|&i| (lo..hi).contains(&i)))
                    .copied()
                    .collect();
                let (surface, nodes) = surface_of(positions, &faces);
                UsdBody {
                    nodes,
                    triangles: surface.triangles,
                    points: String::new(),
                    ratios: String::new(),
                }
            })
            .collect();
        UsdSeries {
            bodies,
            frame_time,
            frames: Vec::new(),
            doc: doc.replace(['"', '\\', '\n'], " "),
        }
    }

    /// Adds `state` as frame `frame` (frames in increasing order).
    pub fn add(&mut self, frame: u32, model: &Model, state: &State) {
        let data = FrameData::new(model, state, OutputUnits::Simulation);
        for body in &mut self.bodies {
            let _ = write!(body.points, "            {frame}: [");
            for (k, &i) in body.nodes.iter().enumerate() {
                let p = data.positions[i].as_vec3();
                let sep = if k == 0 { "" } else { ", " };
                let _ = write!(body.points, "{sep}({:?}, {:?}, {:?})", p.x, p.y, p.z);
            }
            body.points.push_str("],\n");
            let _ = write!(body.ratios, "            {frame}: [");
            for (k, &i) in body.nodes.iter().enumerate() {
                let sep = if k == 0 { "" } else { ", " };
                let _ = write!(body.ratios, "{sep}{:?}", data.node_ratio[i] as f32);
            }
            body.ratios.push_str("],\n");
        }
        self.frames.push(frame);
    }

    /// The frames added so far.
    pub fn frames(&self) -> &[u32] {
        &self.frames
    }

    /// The stage's text.
    pub fn text(&self) -> String {
        let first = self.frames.first().copied().unwrap_or(0);
        let last = self.frames.last().copied().unwrap_or(0);
        let mut out = String::new();
        let _ = write!(
            out,
            "#usda 1.0\n(\n    defaultPrim = \"World\"\n    doc = \"{}\"\n    \
             endTimeCode = {last}\n    metersPerUnit = 1\n    startTimeCode = {first}\n    \
             timeCodesPerSecond = {:?}\n    upAxis = \"Y\"\n)\n\ndef Xform \"World\"\n{{\n",
            self.doc,
            1.0 / self.frame_time
        );
        for (k, body) in self.bodies.iter().enumerate() {
            let counts = vec!["3"; body.triangles.len()].join(", ");
            let indices = (body.triangles.iter().flatten())
                .map(u32::to_string)
                .collect::<Vec<_>>()
                .join(", ");
            let _ = write!(
                out,
                "    def Mesh \"body_{k}\"\n    {{\n        \
                 int[] faceVertexCounts = [{counts}]\n        \
                 int[] faceVertexIndices = [{indices}]\n        \
                 point3f[] points.timeSamples = {{\n{}        }}\n        \
                 float[] primvars:volume_ratio (\n            interpolation = \"vertex\"\n        )\n        \
                 float[] primvars:volume_ratio.timeSamples = {{\n{}        }}\n        \
                 uniform token subdivisionScheme = \"none\"\n    }}\n",
                body.points, body.ratios
            );
        }
        out.push_str("}\n");
        out
    }

    /// Writes the stage to `path` (through a temporary file and a rename: a reader never
    /// sees half a stage).
    pub fn write(&self, path: &Path) -> Result<()> {
        let text = self.text();
        Ok(io::write_atomic(path, |w| w.write_all(text.as_bytes()))?)
    }
}
