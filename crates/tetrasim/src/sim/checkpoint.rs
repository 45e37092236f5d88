//! Checkpoints: a run's whole state in one file, so that a run killed after hours resumes
//! where it was saved and continues bit for bit as if it had never stopped. A checkpoint
//! holds the positions and velocities, what the backend's steps carry from one to the next
//! ([`Carried`]: its clocks, warm-started multipliers, the finite elements' forces), the
//! driver's progress (frames and the record's series so far) and, to refuse resuming on
//! another problem, the parameters, the backend's name and a checksum of the model's start.
//!
//! The file (version [`CHECKPOINT_VERSION`]): the line `tetrasim checkpoint`, the version
//! (u32, little-endian), the header's length (u64) and the header (JSON: what is above, and
//! the arrays' names and lengths), then every value as a little-endian f64 (positions,
//! velocities, the arrays in the header's order), then a CRC-32 of everything before it.
//! It is written to a temporary name and renamed, so a run killed while saving leaves the
//! last checkpoint whole. A file that is not a checkpoint, of another version, truncated
//! or corrupt, or saved on another problem, is refused with a message that says which.

use std::path::Path;

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::{Progress, Simulation};
use crate::backend::{flatten, unflatten, Backend, Carried, State};
use crate::error::{Error, Result};
use crate::mesh::io;
use crate::model::Model;
use crate::params::SimParams;

/// The format version this build writes and reads.
pub const CHECKPOINT_VERSION: u32 = 1;

/// The file's first bytes.
const MAGIC: &[u8] = b"tetrasim checkpoint\n";

/// The JSON header.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct Header {
    backend: String,
    params: SimParams,
    nodes: usize,
    tets: usize,
    /// CRC-32 of the model's start: positions, velocities, masses and tets.
    model_crc: u32,
    frames: u32,
    steps: u64,
    progress: Progress,
    /// Each carried array's name and length.
    arrays: Vec<(String, usize)>,
}

/// A saved run ([module docs](self)).
#[derive(Debug, Clone)]
pub struct Checkpoint {
    header: Header,
    /// The positions and velocities.
    pub state: State,
    /// What the backend's steps carry.
    pub carried: Carried,
}

impl Checkpoint {
    /// The checkpoint of `backend` running `params` on `model`, driven by `driver`. A run
    /// that diverged is not saved.
    pub fn take(
        model: &Model,
        params: &SimParams,
        backend: &mut dyn Backend,
        driver: &Simulation,
    ) -> Result<Self> {
        if let Some(divergence) = &driver.divergence {
            return Err(Error::param(
                "checkpoint",
                format!("a run that diverged is not saved ({divergence})"),
            ));
        }
        let carried = backend.carried()?;
        let state = backend.state()?;
        let header = Header {
            backend: backend.name().to_string(),
            params: params.clone(),
            nodes: model.node_count(),
            tets: model.tets.len(),
            model_crc: model_crc(model),
            frames: carried.frames,
            steps: carried.steps,
            progress: driver.progress(),
            arrays: (carried.arrays.iter())
                .map(|(name, values)| (name.clone(), values.len()))
                .collect(),
        };
        Ok(Checkpoint {
            header,
            state,
            carried,
        })
    }

    /// Frames the saved run had completed.
    pub fn frames(&self) -> u32 {
        self.header.progress.frames
    }

    /// The backend that saved it.
    pub fn backend(&self) -> &str {
        &self.header.backend
    }

    /// The file's bytes.
    pub fn to_bytes(&self) -> Result<Vec<u8>> {
        let header = serde_json::to_vec(&self.header)
            .map_err(|e| Error::param("checkpoint", format!("cannot encode its header: {e}")))?;
        let mut out = MAGIC.to_vec();
        out.extend(CHECKPOINT_VERSION.to_le_bytes());
        out.extend((header.len() as u64).to_le_bytes());
        out.extend(header);
        let vectors = [&self.state.positions, &self.state.velocities];
        let values = (vectors.iter().flat_map(|v| flatten(v))).chain(
            self.carried
                .arrays
                .iter()
                .flat_map(|(_, v)| v.iter().copied()),
        );
        for value in values {
            out.extend(value.to_le_bytes());
        }
        let crc = crc32fast::hash(&out);
        out.extend(crc.to_le_bytes());
        Ok(out)
    }

    /// Writes it to `path`, through a temporary file and a rename.
    pub fn write(&self, path: &Path) -> Result<()> {
        let bytes = self.to_bytes()?;
        Ok(io::write_atomic(path, |w| w.write_all(&bytes))?)
    }

    /// Reads the checkpoint at `path`; errors name the file and what is wrong with it.
    pub fn read(path: &Path) -> Result<Self> {
        let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
        Self::from_bytes(&bytes).map_err(|message| Error::parse(path, None, message))
    }

    /// The checkpoint in `bytes`, or what is wrong with them.
    pub fn from_bytes(bytes: &[u8]) -> std::result::Result<Self, String> {
        let rest = bytes
            .strip_prefix(MAGIC)
            .ok_or("not a tetrasim checkpoint (it does not begin with `tetrasim checkpoint`)")?;
        let (version, rest) = take_u32(rest).ok_or("truncated within its first bytes")?;
        if version != CHECKPOINT_VERSION {
            return Err(format!(
                "a checkpoint of format version {version}; this tetrasim reads version \
                 {CHECKPOINT_VERSION}"
            ));
        }
        let (length, rest) = take_u64(rest).ok_or("truncated within its first bytes")?;
        let header = usize::try_from(length)
            .ok()
            .and_then(|length| rest.get(..length))
            .ok_or_else(|| {
                format!(
                    "truncated: its header is {length} bytes, and {} follow",
                    rest.len()
                )
            })?;
        let header: Header =
            serde_json::from_slice(header).map_err(|e| format!("its header is corrupt: {e}"))?;
        let rest = &rest[length as usize..];
        let values = header
            .arrays
            .iter()
            .try_fold(header.nodes.checked_mul(6), |sum, (_, len)| {
                sum.and_then(|s| s.checked_add(*len)).map(Some)
            })
            .flatten()
            .ok_or("its header's array lengths overflow")?;
        let expected = values.checked_mul(8).and_then(|b| b.checked_add(4));
        if expected != Some(rest.len()) {
            return Err(format!(
                "truncated or padded: its header announces {values} values ({} bytes with the \
                 checksum), and {} bytes follow it",
                expected.map_or("too many".to_string(), |b| b.to_string()),
                rest.len()
            ));
        }
        let (payload, crc) = bytes.split_at(bytes.len() - 4);
        let crc = u32::from_le_bytes([crc[0], crc[1], crc[2], crc[3]]);
        // A fuzzer's inputs rarely carry a right checksum: under cargo-fuzz the checks
        // behind it are reached without one.
        if crc32fast::hash(payload) != crc && !cfg!(fuzzing) {
            return Err("corrupt: its checksum does not match its content".to_string());
        }
        let mut values = rest[..rest.len() - 4]
            .chunks_exact(8)
            .map(|c| f64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]));
        let mut take = |n: usize| values.by_ref().take(n).collect::<Vec<f64>>();
        let n = header.nodes;
        let state = State {
            positions: unflatten(&take(3 * n)),
            velocities: unflatten(&take(3 * n)),
        };
        let arrays = (header.arrays.iter())
            .map(|(name, len)| (name.clone(), take(*len)))
            .collect();
        let carried = Carried {
            frames: header.frames,
            steps: header.steps,
            arrays,
        };
        Ok(Checkpoint {
            header,
            state,
            carried,
        })
    }

    /// Refuses to resume on another problem: another backend, mesh (or placement, pins,
    /// masses) or parameters, each named.
    pub fn check(&self, model: &Model, params: &SimParams, backend: &str) -> Result<()> {
        let h = &self.header;
        let refuse = |message: String| Err(Error::param("checkpoint", message));
        if h.backend != backend {
            return refuse(format!(
                "saved by the {} backend, and this run is on {backend}: a checkpoint resumes \
                 on the backend that saved it",
                h.backend
            ));
        }
        if (h.nodes, h.tets) != (model.node_count(), model.tets.len()) {
            return refuse(format!(
                "saved on another mesh: {} nodes and {} tets, and this run has {} and {}",
                h.nodes,
                h.tets,
                model.node_count(),
                model.tets.len()
            ));
        }
        if h.model_crc != model_crc(model) {
            return refuse(
                "saved on another start: the same counts of nodes and tets, but other \
                 positions, velocities, masses, pins or tets (another mesh or placement)"
                    .to_string(),
            );
        }
        if &h.params != params {
            let (saved, now) = (to_map(&h.params), to_map(params));
            let key = (saved.iter())
                .find(|(k, v)| now.get(*k) != Some(*v))
                .map(|(k, _)| k.clone())
                .unwrap_or_default();
            let show = |m: &serde_json::Map<String, serde_json::Value>| {
                m.get(&key).map_or("none".to_string(), |v| v.to_string())
            };
            return refuse(format!(
                "saved with another `{key}`: {} there, {} in this run",
                show(&saved),
                show(&now)
            ));
        }
        Ok(())
    }

    /// Puts `backend` and `driver` where the saved run was, after [`Checkpoint::check`].
    pub fn resume(
        &self,
        model: &Model,
        params: &SimParams,
        backend: &mut dyn Backend,
        driver: &mut Simulation,
    ) -> Result<()> {
        self.check(model, params, backend.name())?;
        backend.restore(&self.state, &self.carried)?;
        driver.resume(self.header.progress.clone());
        Ok(())
    }
}

/// `params` as a JSON object.
fn to_map(params: &SimParams) -> serde_json::Map<String, serde_json::Value> {
    match serde_json::to_value(params) {
        Ok(serde_json::Value::Object(map)) => map,
        _ => serde_json::Map::new(),
    }
}

/// CRC-32 of the model's start ([`Header::model_crc`]).
fn model_crc(model: &Model) -> u32 {
    let mut hasher = crc32fast::Hasher::new();
    let vectors =
        |v: &[DVec3]| -> Vec<u8> { flatten(v).iter().flat_map(|x| x.to_le_bytes()).collect() };
    hasher.update(&vectors(&model.positions));
    hasher.update(&vectors(&model.velocities));
    for m in model.mass.iter().chain(&model.inv_mass) {
        hasher.update(&m.to_le_bytes());
    }
    for tet in &model.tets {
        for i in tet {
            hasher.update(&i.to_le_bytes());
        }
    }
    hasher.finalize()
}

fn take_u32(bytes: &[u8]) -> Option<(u32, &[u8])> {
    let (head, rest) = bytes.split_first_chunk::<4>()?;
    Some((u32::from_le_bytes(*head), rest))
}

fn take_u64(bytes: &[u8]) -> Option<(u64, &[u8])> {
    let (head, rest) = bytes.split_first_chunk::<8>()?;
    Some((u64::from_le_bytes(*head), rest))
}
