//! Specialization constants set by name: [`SpecValues`] holds a value per [`Spec`] of
//! the one table ([`super::spec_ids`]), whose ids every kernel shares.

pub use super::spec_ids::{flat_vertex, Spec, SpecConst, SpecType, SPEC_CONSTANTS};

/// Values of specialization constants, by name, in the order they were set.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct SpecValues(Vec<(Spec, u32)>, Vec<u32>);

impl SpecValues {
    pub fn new() -> SpecValues {
        SpecValues::default()
    }

    /// These values with `spec` set to `value` (a `bool` as 0 or 1, an `int` or a
    /// `float` as its bits).
    pub fn with(mut self, spec: Spec, value: u32) -> SpecValues {
        self.set(spec, value);
        self
    }

    /// Sets `spec` to `value`, replacing a value set before.
    pub fn set(&mut self, spec: Spec, value: u32) {
        match self.0.iter_mut().find(|(s, _)| *s == spec) {
            Some(entry) => entry.1 = value,
            None => self.0.push((spec, value)),
        }
    }

    /// These values with every value of `other` set too (replacing any set before).
    pub fn with_all(mut self, other: &SpecValues) -> SpecValues {
        other.iter().for_each(|(s, v)| self.set(s, v));
        if !other.1.is_empty() {
            self.1 = other.1.clone();
        }
        self
    }

    /// These values with the vertex words of the first primitives tested in turn
    /// (`spec_ids::flat_vertex`: word i of primitive k at `9 k + i`, as f32 bits).
    pub fn with_flat_vertices(mut self, words: &[u32]) -> SpecValues {
        self.1 = words.to_vec();
        self
    }

    /// The value set for `spec`.
    pub fn get(&self, spec: Spec) -> Option<u32> {
        self.0.iter().find(|(s, _)| *s == spec).map(|&(_, v)| v)
    }

    /// The constants set, by name.
    pub fn iter(&self) -> impl Iterator<Item = (Spec, u32)> + '_ {
        self.0.iter().copied()
    }

    /// `(constant_id, value)` of every constant set.
    pub fn ids(&self) -> Vec<(u32, u32)> {
        let named = self.0.iter().map(|&(s, v)| (s.id(), v));
        let vertices = self.1.iter().enumerate().map(|(j, &v)| {
            let j = j as u32;
            (flat_vertex(j / 9, j % 9).0, v)
        });
        named.chain(vertices).collect()
    }
}

impl FromIterator<(Spec, u32)> for SpecValues {
    fn from_iter<I: IntoIterator<Item = (Spec, u32)>>(iter: I) -> SpecValues {
        let mut values = SpecValues::new();
        for (s, v) in iter {
            values.set(s, v);
        }
        values
    }
}

/// The specialization constants a SPIR-V module declares: `(SpecId, name)` of every
/// `OpSpecConstant*` decorated `SpecId` (the name from its `OpName`, empty if none).
pub fn declared(spirv: &[u8]) -> Vec<(u32, String)> {
    const OP_NAME: u32 = 5;
    const OP_DECORATE: u32 = 71;
    const DECORATION_SPEC_ID: u32 = 1;
    let words: Vec<u32> = spirv
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    let mut names = std::collections::HashMap::new();
    let mut ids = Vec::new();
    let mut at = 5;
    while at < words.len() {
        let (count, opcode) = ((words[at] >> 16) as usize, words[at] & 0xffff);
        if count == 0 || at + count > words.len() {
            break;
        }
        let operands = &words[at + 1..at + count];
        match opcode {
            OP_NAME if !operands.is_empty() => {
                let bytes: Vec<u8> = operands[1..].iter().flat_map(|w| w.to_le_bytes()).collect();
                let end = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
                names.insert(
                    operands[0],
                    String::from_utf8_lossy(&bytes[..end]).into_owned(),
                );
            }
            OP_DECORATE if operands.len() == 3 && operands[1] == DECORATION_SPEC_ID => {
                ids.push((operands[0], operands[2]));
            }
            _ => {}
        }
        at += count;
    }
    ids.into_iter()
        .map(|(result, id)| (id, names.get(&result).cloned().unwrap_or_default()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_has_each_constant_once() {
        let mut ids: Vec<u32> = SPEC_CONSTANTS.iter().map(|c| c.spec.id()).collect();
        let mut names: Vec<&str> = SPEC_CONSTANTS.iter().map(|c| c.name).collect();
        ids.sort();
        ids.dedup();
        names.sort();
        names.dedup();
        assert_eq!(ids.len(), SPEC_CONSTANTS.len(), "an id twice");
        assert_eq!(names.len(), SPEC_CONSTANTS.len(), "a name twice");
    }

    /// Every kernel's SPIR-V (every variant) declares its specialization constants with
    /// the table's ids and names: the GLSL side and the Rust side agree.
    #[test]
    fn kernels_declare_the_tables_ids() {
        let mut checked = 0;
        for (kernel, spirv) in super::super::shaders::ALL {
            if kernel.starts_with("TESTS_") {
                continue; // test kernels number their own constants
            }
            for (id, name) in declared(spirv) {
                if let Some((k, i)) = name
                    .strip_prefix("FLAT_P")
                    .and_then(|r| r.split_once('_'))
                    .and_then(|(k, i)| Some((k.parse().ok()?, i.parse().ok()?)))
                {
                    assert_eq!(flat_vertex(k, i), (id, name.clone()), "{kernel}");
                    checked += 1;
                    continue;
                }
                let row = SPEC_CONSTANTS
                    .iter()
                    .find(|c| c.name == name)
                    .unwrap_or_else(|| panic!("{kernel}: constant {name} is not in the table"));
                assert_eq!(
                    row.spec.id(),
                    id,
                    "{kernel}: {name} has constant_id {id}, the table says {}",
                    row.spec.id()
                );
                checked += 1;
            }
        }
        assert!(checked > 50, "only {checked} constants found");
    }

    #[test]
    fn values_are_set_by_name() {
        let v = SpecValues::new()
            .with(Spec::Textures, 3)
            .with(Spec::Integrator, 7)
            .with(Spec::Textures, 5);
        assert_eq!(v.get(Spec::Textures), Some(5));
        assert_eq!(v.get(Spec::BvhDepth), None);
        assert_eq!(v.ids(), vec![(2, 5), (0, 7)]);
    }
}
