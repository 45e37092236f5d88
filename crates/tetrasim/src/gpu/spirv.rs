//! Test support: a minimal SPIR-V reader, just enough for the unit tests to check that the
//! compiled shaders agree with the host (struct offsets, array strides, bindings; see
//! `gpu/layout.rs` and `render/layout.rs`) and which capabilities a module declares. Only
//! compiled under `cfg(test)`, so it is no part of the public API.

use std::collections::HashMap;

use crate::error::{Error, Result};

const MAGIC: u32 = 0x0723_0203;
const OP_NAME: u32 = 5;
const OP_MEMBER_NAME: u32 = 6;
const OP_CAPABILITY: u32 = 17;
const OP_TYPE_STRUCT: u32 = 30;
const OP_TYPE_POINTER: u32 = 32;
const OP_VARIABLE: u32 = 59;
const OP_DECORATE: u32 = 71;
const OP_MEMBER_DECORATE: u32 = 72;
const DECORATION_ARRAY_STRIDE: u32 = 6;
const DECORATION_BINDING: u32 = 33;
const DECORATION_OFFSET: u32 = 35;
const STORAGE_UNIFORM: u32 = 2;
const STORAGE_STORAGE_BUFFER: u32 = 12;

/// `AtomicFloat32AddEXT`: the capability of `atomicAdd` on float.
pub const CAPABILITY_ATOMIC_FLOAT32_ADD: u32 = 6033;

/// The parts of a module the checks need.
#[derive(Debug, Default)]
pub struct Module {
    capabilities: Vec<u32>,
    names: HashMap<u32, String>,
    member_names: HashMap<(u32, u32), String>,
    member_offsets: HashMap<(u32, u32), u32>,
    decorations: HashMap<(u32, u32), u32>,
    struct_members: HashMap<u32, Vec<u32>>,
    pointers: HashMap<u32, u32>,
    variables: Vec<(u32, u32, u32)>,
}

fn string(words: &[u32]) -> String {
    let bytes: Vec<u8> = words
        .iter()
        .flat_map(|w| w.to_le_bytes())
        .take_while(|&b| b != 0)
        .collect();
    String::from_utf8_lossy(&bytes).into_owned()
}

impl Module {
    /// Parses SPIR-V bytes (little-endian words).
    pub fn parse(bytes: &[u8]) -> Result<Self> {
        if bytes.len() % 4 != 0 || bytes.len() < 20 {
            return Err(Error::Gpu(format!(
                "SPIR-V of {} bytes is not a whole module",
                bytes.len()
            )));
        }
        let words: Vec<u32> = bytes
            .chunks_exact(4)
            .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        if words[0] != MAGIC {
            return Err(Error::Gpu(format!(
                "SPIR-V magic is {:#x}, expected {MAGIC:#x}",
                words[0]
            )));
        }
        let mut m = Module::default();
        let mut at = 5;
        while at < words.len() {
            let count = (words[at] >> 16) as usize;
            let op = words[at] & 0xffff;
            let ins = words.get(at..at + count).filter(|_| count > 0).ok_or_else(|| {
                Error::Gpu(format!("SPIR-V instruction at word {at} (op {op}, {count} words) runs past the end"))
            })?;
            let arg = |i: usize| ins.get(i).copied().unwrap_or(0);
            match op {
                OP_CAPABILITY => m.capabilities.push(arg(1)),
                OP_NAME => {
                    m.names.insert(arg(1), string(&ins[2.min(count)..]));
                }
                OP_MEMBER_NAME => {
                    m.member_names
                        .insert((arg(1), arg(2)), string(&ins[3.min(count)..]));
                }
                OP_TYPE_STRUCT => {
                    m.struct_members
                        .insert(arg(1), ins[2.min(count)..].to_vec());
                }
                OP_TYPE_POINTER => {
                    m.pointers.insert(arg(1), arg(3));
                }
                OP_VARIABLE => m.variables.push((arg(1), arg(2), arg(3))),
                OP_DECORATE if count >= 4 => {
                    m.decorations.insert((arg(1), arg(2)), arg(3));
                }
                OP_MEMBER_DECORATE if arg(3) == DECORATION_OFFSET => {
                    m.member_offsets.insert((arg(1), arg(2)), arg(4));
                }
                _ => {}
            }
            at += count;
        }
        Ok(m)
    }

    /// Whether the module declares `capability`.
    pub fn has_capability(&self, capability: u32) -> bool {
        self.capabilities.contains(&capability)
    }

    /// `(member name, byte offset)` of the first struct named `name` that has offsets.
    pub fn struct_offsets(&self, name: &str) -> Vec<(String, u32)> {
        let mut ids: Vec<u32> = self
            .names
            .iter()
            .filter(|(_, n)| *n == name)
            .map(|(id, _)| *id)
            .collect();
        ids.sort_unstable();
        for id in ids {
            let Some(members) = self.struct_members.get(&id) else {
                continue;
            };
            let found: Vec<(String, u32)> = (0..members.len() as u32)
                .filter_map(|i| {
                    Some((
                        self.member_names.get(&(id, i))?.clone(),
                        *self.member_offsets.get(&(id, i))?,
                    ))
                })
                .collect();
            if !found.is_empty() {
                return found;
            }
        }
        Vec::new()
    }

    /// Array stride of the runtime array that is the first member of the block `name`.
    pub fn array_stride(&self, name: &str) -> Option<u32> {
        let (id, _) = self
            .names
            .iter()
            .find(|(id, n)| *n == name && self.struct_members.contains_key(id))?;
        let array = *self.struct_members.get(id)?.first()?;
        self.decorations
            .get(&(array, DECORATION_ARRAY_STRIDE))
            .copied()
    }

    /// `(block type name, binding)` of every buffer variable.
    pub fn block_bindings(&self) -> Vec<(String, u32)> {
        self.variables
            .iter()
            .filter(|(_, _, storage)| {
                *storage == STORAGE_STORAGE_BUFFER || *storage == STORAGE_UNIFORM
            })
            .filter_map(|(pointer, id, _)| {
                let block = self.pointers.get(pointer)?;
                Some((
                    self.names.get(block)?.clone(),
                    *self.decorations.get(&(*id, DECORATION_BINDING))?,
                ))
            })
            .collect()
    }
}

/// Checks that every member of the struct `block` in each shader of `keys`
/// sits at the offset `rust` gives for that name (a member Rust lacks fails too), that each
/// shader has the block, and returns how many members were checked. For the layout tests.
#[cfg(test)]
pub(crate) fn assert_struct_offsets(keys: &[&str], block: &str, rust: &[(&str, usize)]) -> usize {
    let mut checked = 0;
    for key in keys {
        let bytes = crate::gpu::kernel::shader(key).unwrap();
        let offsets = Module::parse(bytes).unwrap().struct_offsets(block);
        assert!(!offsets.is_empty(), "{key}: no {block} block found");
        for (name, offset) in offsets {
            let expected = rust
                .iter()
                .find(|(n, _)| *n == name)
                .map(|(_, o)| *o as u32);
            assert_eq!(Some(offset), expected, "{key}: member `{name}`");
            checked += 1;
        }
    }
    checked
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_ext_variants_declare_the_float_atomic_capability() {
        let mut variants = 0;
        for (key, bytes) in crate::shaders::SHADERS {
            let m = Module::parse(bytes).unwrap();
            let declared = m.has_capability(CAPABILITY_ATOMIC_FLOAT32_ADD);
            assert_eq!(
                declared,
                key.ends_with("#ext"),
                "{key}: AtomicFloat32AddEXT declared = {declared}"
            );
            variants += usize::from(key.contains('#'));
        }
        // spring_scatter, spring_constraint, distance, volume, inversion_floor,
        // contact_solve: ext + cas each; spring_constraint, distance, volume,
        // inversion_floor: gather; spring_constraint, distance, volume, inversion_floor: block;
        // constraint_apply: sums, gather,
        // chebyshev, gather_chebyshev, sums_colliders, gather_colliders; global_volume,
        // global_volume_sum, integrate, contact_apply and anderson_mix: colliders (their
        // `plain` variants keep
        // the shader's own key); integrate: split, colliders_split; split_velocity:
        // colliders; contact_measure: colliders, bodies, colliders_bodies; minres_setup and
        // minres_forces: colliders; minres_rows: one per mix of its four row segments (15);
        // minres_finish: s, v, sv; elastic_contacts, elastic_start, elastic and
        // elastic_rigid_part: colliders; reactions: elastic.
        assert_eq!(variants, 62);
    }

    #[test]
    fn rejects_truncated_modules() {
        assert!(Module::parse(&[0u8; 8]).is_err());
        let mut bytes = crate::shaders::SHADERS[0].1.to_vec();
        bytes[0] ^= 0xff;
        assert!(Module::parse(&bytes)
            .unwrap_err()
            .to_string()
            .contains("magic"));
    }
}
