//! A small SPIR-V reader: the names, decorations, types, constants, variables and execution
//! modes of one module, which is all the mirror test compares (numbers from the SPIR-V
//! specification, section 3).

use std::collections::{HashMap, HashSet};

const MAGIC: u32 = 0x0723_0203;
const HEADER_WORDS: usize = 5;

// Opcodes.
const OP_NAME: u32 = 5;
const OP_MEMBER_NAME: u32 = 6;
const OP_ENTRY_POINT: u32 = 15;
const OP_EXECUTION_MODE: u32 = 16;
const OP_TYPE_BOOL: u32 = 20;
const OP_TYPE_INT: u32 = 21;
const OP_TYPE_FLOAT: u32 = 22;
const OP_TYPE_VECTOR: u32 = 23;
const OP_TYPE_IMAGE: u32 = 25;
const OP_TYPE_ARRAY: u32 = 28;
const OP_TYPE_RUNTIME_ARRAY: u32 = 29;
const OP_TYPE_STRUCT: u32 = 30;
const OP_TYPE_POINTER: u32 = 32;
const OP_CONSTANT_TRUE: u32 = 41;
const OP_CONSTANT_FALSE: u32 = 42;
const OP_CONSTANT: u32 = 43;
const OP_SPEC_CONSTANT_TRUE: u32 = 48;
const OP_SPEC_CONSTANT_FALSE: u32 = 49;
const OP_SPEC_CONSTANT: u32 = 50;
const OP_VARIABLE: u32 = 59;
const OP_DECORATE: u32 = 71;
const OP_MEMBER_DECORATE: u32 = 72;
const OP_EXECUTION_MODE_ID: u32 = 331;
// Opcodes inside functions that name a pointer: what makes a variable statically used.
const OP_FUNCTION_CALL: u32 = 57;
const OP_LOAD: u32 = 61;
const OP_STORE: u32 = 62;
const OP_COPY_MEMORY: u32 = 63;
const OP_COPY_MEMORY_SIZED: u32 = 64;
const OP_ACCESS_CHAIN: u32 = 65;
const OP_IN_BOUNDS_ACCESS_CHAIN: u32 = 66;
const OP_PTR_ACCESS_CHAIN: u32 = 67;
const OP_ARRAY_LENGTH: u32 = 68;
const OP_IN_BOUNDS_PTR_ACCESS_CHAIN: u32 = 70;
const OP_ATOMIC_LOAD: u32 = 227;
const OP_ATOMIC_STORE: u32 = 228;
const OP_ATOMIC_XOR: u32 = 242;
const OP_ATOMIC_FMIN_EXT: u32 = 5614;
const OP_ATOMIC_FMAX_EXT: u32 = 5615;
const OP_ATOMIC_FADD_EXT: u32 = 6035;

// Decorations.
pub const SPEC_ID: u32 = 1;
pub const ARRAY_STRIDE: u32 = 6;
pub const BINDING: u32 = 33;
pub const DESCRIPTOR_SET: u32 = 34;
pub const OFFSET: u32 = 35;

// Execution models and modes.
pub const VERTEX: u32 = 0;
pub const FRAGMENT: u32 = 4;
pub const GL_COMPUTE: u32 = 5;
pub const LOCAL_SIZE: u32 = 17;
pub const LOCAL_SIZE_ID: u32 = 38;

// Storage classes of what the host binds.
pub const UNIFORM_CONSTANT: u32 = 0;
pub const PUSH_CONSTANT: u32 = 9;
pub const STORAGE_BUFFER: u32 = 12;
// OpTypeImage's Dim for a buffer image, and its Sampled for an image read through a sampler
// (a uniform texel buffer) or read and written without one (a storage texel buffer).
pub const DIM_BUFFER: u32 = 5;
pub const SAMPLED_WITH_SAMPLER: u32 = 1;
pub const SAMPLED_AS_STORAGE: u32 = 2;

/// The types the layouts are made of, and images (the texel views: `Image`'s `dim` and
/// `sampled` as OpTypeImage gives them, `DIM_BUFFER` and `SAMPLED_*` above); the reader skips
/// the rest (functions, matrices), which no shared layout holds.
#[derive(Clone, Debug, PartialEq)]
pub enum Type {
    Bool,
    Int { width: u32 },
    Float { width: u32 },
    Vector { component: u32, count: u32 },
    Array { element: u32, length: u32 },
    RuntimeArray { element: u32 },
    Struct { members: Vec<u32> },
    Pointer { storage: u32, pointee: u32 },
    Image { dim: u32, sampled: u32 },
}

/// A constant's value (its first word; booleans 0 or 1) and whether the pipeline may
/// specialize it.
#[derive(Clone, Copy, Debug)]
pub struct Constant {
    pub ty: u32,
    pub value: u32,
    pub spec: bool,
}

/// A global variable: its pointer type and storage class.
#[derive(Clone, Copy, Debug)]
pub struct Variable {
    pub id: u32,
    pub pointer: u32,
    pub storage: u32,
}

/// One execution mode of an entry point, its operands literal (`OpExecutionMode`) or ids
/// (`OpExecutionModeId`).
#[derive(Clone, Debug)]
pub struct ExecutionMode {
    pub mode: u32,
    pub operands: Vec<u32>,
    pub ids: bool,
}

/// Decorations of one id or member: each decoration with its literal operands.
pub type Decorations = Vec<(u32, Vec<u32>)>;

/// What the mirror reads of one module.
#[derive(Debug, Default)]
pub struct Module {
    /// Execution model of each entry point.
    pub models: Vec<u32>,
    pub names: HashMap<u32, String>,
    pub member_names: HashMap<(u32, u32), String>,
    pub decorations: HashMap<u32, Decorations>,
    /// Decorations of a struct member, keyed by (struct, member).
    pub member_decorations: HashMap<(u32, u32), Decorations>,
    pub types: HashMap<u32, Type>,
    pub constants: HashMap<u32, Constant>,
    pub variables: Vec<Variable>,
    /// Ids the functions load, store, index or pass as pointers: a variable among them is
    /// statically used (the shader's resource interface, which the pipeline layout must
    /// cover; a declared but unused block needs nothing).
    pub accessed: HashSet<u32>,
    pub execution_modes: Vec<ExecutionMode>,
}

/// A literal string's text (nul-terminated, packed little-end first into words) and how many
/// words it took.
fn string(words: &[u32]) -> (String, usize) {
    let mut bytes = Vec::new();
    for (i, word) in words.iter().enumerate() {
        for byte in word.to_le_bytes() {
            if byte == 0 {
                return (String::from_utf8_lossy(&bytes).into_owned(), i + 1);
            }
            bytes.push(byte);
        }
    }
    (String::from_utf8_lossy(&bytes).into_owned(), words.len())
}

impl Module {
    /// Reads a module from its bytes (either byte order).
    pub fn parse(bytes: &[u8]) -> Result<Module, String> {
        if bytes.len() % 4 != 0 || bytes.len() < 4 * HEADER_WORDS {
            return Err(format!("{} bytes is not a SPIR-V module", bytes.len()));
        }
        let mut words: Vec<u32> = bytes
            .chunks_exact(4)
            .map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]]))
            .collect();
        if words[0] == MAGIC.swap_bytes() {
            words.iter_mut().for_each(|w| *w = w.swap_bytes());
        } else if words[0] != MAGIC {
            return Err(format!("bad magic number {:#010x}", words[0]));
        }
        let mut module = Module::default();
        let mut at = HEADER_WORDS;
        while at < words.len() {
            let count = (words[at] >> 16) as usize;
            let opcode = words[at] & 0xffff;
            if count == 0 || at + count > words.len() {
                return Err(format!("instruction at word {at} has a bad length {count}"));
            }
            module.read(opcode, &words[at + 1..at + count])?;
            at += count;
        }
        Ok(module)
    }

    /// Takes in one instruction's operands.
    fn read(&mut self, opcode: u32, op: &[u32]) -> Result<(), String> {
        let short = || format!("opcode {opcode} has too few operands ({})", op.len());
        let need = |n: usize| if op.len() < n { Err(short()) } else { Ok(()) };
        match opcode {
            OP_NAME => {
                need(2)?;
                self.names.insert(op[0], string(&op[1..]).0);
            }
            OP_MEMBER_NAME => {
                need(3)?;
                self.member_names.insert((op[0], op[1]), string(&op[2..]).0);
            }
            OP_ENTRY_POINT => {
                need(3)?;
                self.models.push(op[0]);
            }
            OP_EXECUTION_MODE | OP_EXECUTION_MODE_ID => {
                need(2)?;
                self.execution_modes.push(ExecutionMode {
                    mode: op[1],
                    operands: op[2..].to_vec(),
                    ids: opcode == OP_EXECUTION_MODE_ID,
                });
            }
            OP_TYPE_BOOL => self.define(op, 1, |_| Type::Bool)?,
            OP_TYPE_INT => self.define(op, 3, |op| Type::Int { width: op[1] })?,
            OP_TYPE_FLOAT => self.define(op, 2, |op| Type::Float { width: op[1] })?,
            OP_TYPE_VECTOR => self.define(op, 3, |op| Type::Vector {
                component: op[1],
                count: op[2],
            })?,
            OP_TYPE_ARRAY => self.define(op, 3, |op| Type::Array {
                element: op[1],
                length: op[2],
            })?,
            OP_TYPE_RUNTIME_ARRAY => {
                self.define(op, 2, |op| Type::RuntimeArray { element: op[1] })?
            }
            OP_TYPE_STRUCT => self.define(op, 1, |op| Type::Struct {
                members: op[1..].to_vec(),
            })?,
            OP_TYPE_POINTER => self.define(op, 3, |op| Type::Pointer {
                storage: op[1],
                pointee: op[2],
            })?,
            OP_TYPE_IMAGE => self.define(op, 8, |op| Type::Image {
                dim: op[2],
                sampled: op[6],
            })?,
            OP_CONSTANT_TRUE
            | OP_CONSTANT_FALSE
            | OP_SPEC_CONSTANT_TRUE
            | OP_SPEC_CONSTANT_FALSE => {
                need(2)?;
                let value = matches!(opcode, OP_CONSTANT_TRUE | OP_SPEC_CONSTANT_TRUE) as u32;
                let spec = matches!(opcode, OP_SPEC_CONSTANT_TRUE | OP_SPEC_CONSTANT_FALSE);
                self.constants.insert(
                    op[1],
                    Constant {
                        ty: op[0],
                        value,
                        spec,
                    },
                );
            }
            OP_CONSTANT | OP_SPEC_CONSTANT => {
                need(3)?;
                self.constants.insert(
                    op[1],
                    Constant {
                        ty: op[0],
                        value: op[2],
                        spec: opcode == OP_SPEC_CONSTANT,
                    },
                );
            }
            OP_VARIABLE => {
                need(3)?;
                self.variables.push(Variable {
                    pointer: op[0],
                    id: op[1],
                    storage: op[2],
                });
            }
            OP_DECORATE => {
                need(2)?;
                let entry = (op[1], op[2..].to_vec());
                self.decorations.entry(op[0]).or_default().push(entry);
            }
            OP_MEMBER_DECORATE => {
                need(3)?;
                let entry = (op[2], op[3..].to_vec());
                let key = (op[0], op[1]);
                self.member_decorations.entry(key).or_default().push(entry);
            }
            OP_STORE | OP_ATOMIC_STORE => self.accessed.extend(op.first()),
            OP_COPY_MEMORY | OP_COPY_MEMORY_SIZED => self.accessed.extend(op.iter().take(2)),
            OP_LOAD
            | OP_ACCESS_CHAIN
            | OP_IN_BOUNDS_ACCESS_CHAIN
            | OP_PTR_ACCESS_CHAIN
            | OP_IN_BOUNDS_PTR_ACCESS_CHAIN
            | OP_ARRAY_LENGTH
            | OP_ATOMIC_LOAD..=OP_ATOMIC_XOR
            | OP_ATOMIC_FMIN_EXT
            | OP_ATOMIC_FMAX_EXT
            | OP_ATOMIC_FADD_EXT => self.accessed.extend(op.get(2)),
            OP_FUNCTION_CALL => self.accessed.extend(op.iter().skip(3)),
            _ => {}
        }
        Ok(())
    }

    /// Records a type whose result id is the first operand.
    fn define(
        &mut self,
        op: &[u32],
        min: usize,
        ty: impl Fn(&[u32]) -> Type,
    ) -> Result<(), String> {
        if op.len() < min {
            return Err(format!(
                "a type declaration has too few operands ({})",
                op.len()
            ));
        }
        self.types.insert(op[0], ty(op));
        Ok(())
    }

    /// The first literal of decoration `decoration` on `id`.
    pub fn decoration(&self, id: u32, decoration: u32) -> Option<u32> {
        self.decorations
            .get(&id)?
            .iter()
            .find(|(d, _)| *d == decoration)
            .and_then(|(_, operands)| operands.first().copied())
    }

    /// The first literal of decoration `decoration` on member `member` of struct `id`.
    pub fn member_decoration(&self, id: u32, member: u32, decoration: u32) -> Option<u32> {
        self.member_decorations
            .get(&(id, member))?
            .iter()
            .find(|(d, _)| *d == decoration)
            .and_then(|(_, operands)| operands.first().copied())
    }

    /// The name of `id` (`""` if it has none).
    pub fn name(&self, id: u32) -> &str {
        self.names.get(&id).map_or("", String::as_str)
    }

    /// The member types of struct `id`.
    pub fn members(&self, id: u32) -> Option<&[u32]> {
        match self.types.get(&id)? {
            Type::Struct { members } => Some(members),
            _ => None,
        }
    }

    /// Bytes a value of type `id` takes in an explicitly laid-out block: scalars and vectors
    /// by their width, arrays by their stride, structs up to their last member's end. `None`
    /// for runtime arrays and types the layouts do not use.
    pub fn size_of(&self, id: u32) -> Option<u32> {
        match self.types.get(&id)? {
            // Vulkan passes booleans (specialization constants) as 32-bit `VkBool32`.
            Type::Bool => Some(4),
            Type::Int { width } | Type::Float { width } => Some(width / 8),
            Type::Vector { component, count } => Some(self.size_of(*component)? * count),
            Type::Array { length, .. } => {
                let stride = self.decoration(id, ARRAY_STRIDE)?;
                Some(stride * self.constants.get(length)?.value)
            }
            Type::Struct { members } => {
                let last = members.len().checked_sub(1)?;
                let offset = self.member_decoration(id, last as u32, OFFSET)?;
                Some(offset + self.size_of(members[last])?)
            }
            Type::RuntimeArray { .. } | Type::Pointer { .. } | Type::Image { .. } => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One instruction: its word count and opcode, then its operands.
    fn instruction(opcode: u32, operands: &[u32]) -> Vec<u32> {
        let mut words = vec![((operands.len() as u32 + 1) << 16) | opcode];
        words.extend_from_slice(operands);
        words
    }

    fn module(instructions: &[Vec<u32>]) -> Vec<u8> {
        let mut words = vec![MAGIC, 0x0001_0600, 0, 100, 0];
        words.extend(instructions.iter().flatten());
        words.iter().flat_map(|w| w.to_le_bytes()).collect()
    }

    #[test]
    fn reads_names_struct_offsets_and_sizes() {
        // "ab" fits one word with its nul; "abcd" needs a second for the nul.
        let ab = u32::from_le_bytes(*b"ab\0\0");
        let abcd = u32::from_le_bytes(*b"abcd");
        let bytes = module(&[
            instruction(OP_NAME, &[3, ab]),
            instruction(OP_MEMBER_NAME, &[3, 1, abcd, 0]),
            instruction(OP_MEMBER_DECORATE, &[3, 0, OFFSET, 0]),
            instruction(OP_MEMBER_DECORATE, &[3, 1, OFFSET, 12]),
            instruction(OP_TYPE_FLOAT, &[1, 32]),
            instruction(OP_TYPE_VECTOR, &[2, 1, 3]),
            instruction(OP_TYPE_STRUCT, &[3, 2, 1]),
        ]);
        let m = Module::parse(&bytes).unwrap();
        assert_eq!(m.name(3), "ab");
        assert_eq!(m.member_names[&(3, 1)], "abcd");
        assert_eq!(m.members(3), Some(&[2, 1][..]));
        assert_eq!(m.member_decoration(3, 1, OFFSET), Some(12));
        assert_eq!(m.size_of(2), Some(12));
        assert_eq!(m.size_of(3), Some(16));
    }

    #[test]
    fn reads_spec_constants_and_local_size_ids() {
        let bytes = module(&[
            instruction(OP_EXECUTION_MODE_ID, &[9, LOCAL_SIZE_ID, 5, 6, 6]),
            instruction(OP_DECORATE, &[4, SPEC_ID, 16]),
            instruction(OP_TYPE_BOOL, &[1]),
            instruction(OP_TYPE_INT, &[2, 32, 0]),
            instruction(OP_SPEC_CONSTANT_TRUE, &[1, 4]),
            instruction(OP_CONSTANT, &[2, 5, 256]),
            instruction(OP_CONSTANT, &[2, 6, 1]),
        ]);
        let m = Module::parse(&bytes).unwrap();
        assert_eq!(m.decoration(4, SPEC_ID), Some(16));
        assert!(m.constants[&4].spec && m.constants[&4].value == 1);
        assert!(!m.constants[&5].spec && m.constants[&5].value == 256);
        let mode = &m.execution_modes[0];
        assert!(mode.ids && mode.mode == LOCAL_SIZE_ID && mode.operands == [5, 6, 6]);
    }

    #[test]
    fn a_variable_is_accessed_only_through_a_pointer_operand() {
        let bytes = module(&[
            instruction(OP_VARIABLE, &[1, 7, STORAGE_BUFFER]),
            instruction(OP_VARIABLE, &[1, 8, STORAGE_BUFFER]),
            instruction(OP_VARIABLE, &[1, 9, STORAGE_BUFFER]),
            // %10 = OpAccessChain %ptr %7 %zero; OpAtomicStore %9 %scope %semantics %value
            instruction(OP_ACCESS_CHAIN, &[2, 10, 7, 3]),
            instruction(OP_ATOMIC_STORE, &[9, 4, 5, 6]),
            // A literal 8 (OpCompositeExtract's index) is no use of %8.
            instruction(81, &[2, 11, 12, 8]),
        ]);
        let m = Module::parse(&bytes).unwrap();
        assert!(m.accessed.contains(&7) && m.accessed.contains(&9));
        assert!(!m.accessed.contains(&8));
    }

    #[test]
    fn refuses_what_is_not_spirv() {
        assert!(Module::parse(&[0; 20]).is_err());
        assert!(Module::parse(&[3, 2, 35]).is_err());
        let mut truncated = module(&[instruction(OP_TYPE_INT, &[2, 32, 0])]);
        truncated.truncate(truncated.len() - 4);
        assert!(Module::parse(&truncated).is_err());
    }
}
