//! The CPU-GPU mirror (design §7) checked on the compiled shaders: every SPIR-V module
//! `build.rs` made for this feature set (`spirv-files.txt` in `OUT_DIR`) is read and compared
//! with the Rust side -- the shared structs member by member (names, order, offsets, sizes,
//! array strides), the specialization constants by name (id, width, default), the descriptor
//! bindings (number, stage, block name) and the compute workgroup sizes. A drift on either
//! side fails a test here rather than a frame.

mod reader;
mod rust_layouts;

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::sync::OnceLock;

use ash::vk;

use crate::gpu_layout::SpecConstants;
use crate::renderer::prepass::steps::{GROUP_SIZE, SPLAT_GROUP_SIZE};
use crate::renderer::{
    Binding, OCCLUSION_TILE_WORDS, SHADING_RECORD_STORES, SHADING_RECORD_TEXELS, TEXEL_VIEWS,
    VISIBILITY_KEYS,
};
use reader::{Constant, Module, Type};
use rust_layouts::{shared_layouts, spec_constant_fields, Layout};

/// The builds of this feature set, one a line (written by `build.rs`).
const BUILT: &str = include_str!(concat!(env!("OUT_DIR"), "/spirv-files.txt"));

/// The GLSL side of every shared layout.
const GPU_LAYOUT_GLSL: &str = include_str!("../../glsl/include/gpu_layout.glsl");

/// Buffer blocks that read a binding under a name other than its `Binding` variant's: another
/// view of the same buffer.
const OTHER_VIEWS: [(Binding, &str); 2] = [
    // The draw's read-only view; the pre-pass writes it as `Visible`.
    (Binding::Visible, "VisibleInstances"),
    // The tiled splat's lists read 16 bytes at a time.
    (Binding::TileLists, "TileLists4"),
];

/// A texel buffer of set 0: binding, variable name, the stages the set layout gives it and its
/// descriptor type.
type TexelBinding = (u32, &'static str, vk::ShaderStageFlags, vk::DescriptorType);

/// The texel buffers of set 0.
fn texel_views() -> [TexelBinding; 5] {
    let read =
        |view: crate::renderer::TexelView, name| (view.binding, name, view.stages, view.kind);
    [
        (
            Binding::Instances as u32,
            "instance_texels",
            Binding::Instances.stages(),
            Binding::Instances.descriptor_type(),
        ),
        read(VISIBILITY_KEYS, "visibility_keys"),
        read(OCCLUSION_TILE_WORDS, "occlusion_tile_words"),
        read(SHADING_RECORD_TEXELS, "shading_record_texels"),
        read(SHADING_RECORD_STORES, "shading_record_stores"),
    ]
}

/// A record read as texels: its name, its texels and each field's name and byte offset.
type TexelRecord = (&'static str, usize, &'static [(&'static str, usize)]);

/// The records the shaders read as 16-byte texels (binding 0's uniform texel buffer), which no
/// SPIR-V block lays out: each field at the byte `load_instance` (glsl/include/
/// ellipsoid_common.glsl) takes it from, texel * 16 + component * 4, and the texels a record
/// spans (`instance_texel_count`).
const TEXEL_RECORDS: [TexelRecord; 2] = [
    (
        "Instance",
        3,
        &[
            ("center", 0),
            ("color", 12),
            ("rotation", 16),
            ("radii", 32),
            ("unused", 44),
        ],
    ),
    (
        "CompactInstance",
        2,
        &[
            ("center", 0),
            ("color", 12),
            ("rotation", 16),
            ("radii", 24),
        ],
    ),
];

/// Each compute shader and the workgroup size the Rust side sizes its dispatches by.
fn dispatch_group_sizes() -> Vec<(&'static str, [u64; 3])> {
    let mut sizes = vec![
        ("cull.comp.spv", [GROUP_SIZE, 1, 1]),
        ("splat.comp.spv", [SPLAT_GROUP_SIZE as u64, 1, 1]),
    ];
    // The benchmark's tiled splat: its binning steps per glyph as the splat, its tile pass
    // one lane per column of a tile.
    #[cfg(feature = "research")]
    sizes.extend([
        ("tiled_bins.comp.spv", [SPLAT_GROUP_SIZE as u64, 1, 1]),
        (
            "tiled_splat.comp.spv",
            [crate::renderer::prepass::steps::TILED_TILE as u64, 1, 1],
        ),
    ]);
    // The benchmark's traced path: each glyph's box per glyph as the splat, the traversal
    // one invocation per pixel in squares.
    #[cfg(feature = "research")]
    {
        let edge = crate::research::TRACE_GROUP_EDGE as u64;
        sizes.extend([
            ("traced_boxes.comp.spv", [SPLAT_GROUP_SIZE as u64, 1, 1]),
            ("traced.comp.spv", [edge, edge, 1]),
        ]);
    }
    #[cfg(feature = "offscreen")]
    {
        let edge = crate::offscreen::sample_zero::GROUP_EDGE as u64;
        for file in SAMPLE_ZERO_MODULES {
            sizes.push((file, [edge, edge, 1]));
        }
    }
    sizes
}

/// The offscreen renderer's fetch of sample 0 (`glsl/offscreen/`): a set of its own, not the
/// renderer's `Binding` table.
const SAMPLE_ZERO_MODULES: [&str; 2] = ["sample_zero_depth.comp.spv", "sample_zero_id.comp.spv"];

/// The benchmark's traced path (`glsl/research/`): set 0 is the renderer's, set 1 its own
/// acceleration structure and boxes.
const TRACED_MODULES: [&str; 2] = ["traced.comp.spv", "traced_boxes.comp.spv"];

/// Every module this feature set built, by file name.
fn modules() -> &'static BTreeMap<&'static str, Module> {
    static MODULES: OnceLock<BTreeMap<&'static str, Module>> = OnceLock::new();
    MODULES.get_or_init(|| {
        let out = Path::new(env!("OUT_DIR"));
        let modules: BTreeMap<_, _> = BUILT
            .lines()
            .map(|name| {
                let bytes = std::fs::read(out.join(name))
                    .unwrap_or_else(|e| panic!("{name}: build.rs listed it but: {e}"));
                let module = Module::parse(&bytes).unwrap_or_else(|e| panic!("{name}: {e}"));
                (name, module)
            })
            .collect();
        assert!(modules.len() >= 10, "only {} modules listed", modules.len());
        modules
    })
}

/// The shader stage of a module's entry point.
fn stage(name: &str, module: &Module) -> vk::ShaderStageFlags {
    match module.models.as_slice() {
        [reader::VERTEX] => vk::ShaderStageFlags::VERTEX,
        [reader::FRAGMENT] => vk::ShaderStageFlags::FRAGMENT,
        [reader::GL_COMPUTE] => vk::ShaderStageFlags::COMPUTE,
        models => {
            panic!("{name}: expected one vertex, fragment or compute entry point, found {models:?}")
        }
    }
}

/// Mismatches found, each with the shaders it was found in (most hold in every build).
#[derive(Default)]
struct Findings(BTreeMap<String, Vec<&'static str>>);

impl Findings {
    /// A mismatch in shader `file`.
    fn add(&mut self, file: &'static str, mismatch: String) {
        self.0.entry(mismatch).or_default().push(file);
    }

    /// A mismatch of the whole set of shaders.
    fn add_overall(&mut self, mismatch: String) {
        self.0.entry(mismatch).or_default();
    }

    /// Fails with every mismatch found, one a line.
    fn assert_none(self, what: &str) {
        let lines: Vec<String> = self
            .0
            .into_iter()
            .map(|(mismatch, files)| match files.as_slice() {
                [] => mismatch,
                [one] => format!("{one}: {mismatch}"),
                [first, rest @ ..] => {
                    format!("{first} and {} more: {mismatch}", rest.len())
                }
            })
            .collect();
        assert!(
            lines.is_empty(),
            "{what}: the shaders and the Rust side disagree:\n  {}",
            lines.join("\n  ")
        );
    }
}

/// Compares one explicitly laid-out SPIR-V struct with its Rust type.
fn compare_struct(module: &Module, id: u32, rust: &Layout) -> Vec<String> {
    let mut mismatches = Vec::new();
    let members = module.members(id).unwrap_or_default();
    if members.len() != rust.fields.len() {
        mismatches.push(format!(
            "{} has {} members, the Rust type {} fields",
            rust.name,
            members.len(),
            rust.fields.len()
        ));
    }
    for (index, (&ty, field)) in members.iter().zip(&rust.fields).enumerate() {
        let index = index as u32;
        let name = module
            .member_names
            .get(&(id, index))
            .map_or("", String::as_str);
        let offset = module.member_decoration(id, index, reader::OFFSET);
        let size = module.size_of(ty);
        if name != field.name
            || offset != Some(field.offset as u32)
            || size != Some(field.size as u32)
        {
            mismatches.push(format!(
                "{} member {index}: `{name}` at {offset:?} of {size:?} bytes in SPIR-V, \
                 `{}` at {} of {} bytes in Rust",
                rust.name, field.name, field.offset, field.size
            ));
        }
    }
    if module.size_of(id) != Some(rust.size as u32) {
        mismatches.push(format!(
            "{} takes {:?} bytes in SPIR-V, {} in Rust",
            rust.name,
            module.size_of(id),
            rust.size
        ));
    }
    // Arrays of it step by the Rust size.
    for (&array, ty) in &module.types {
        let element = match ty {
            Type::Array { element, .. } | Type::RuntimeArray { element } => *element,
            _ => continue,
        };
        let stride = module.decoration(array, reader::ARRAY_STRIDE);
        if element == id && stride != Some(rust.size as u32) {
            mismatches.push(format!(
                "arrays of {} step by {stride:?} bytes in SPIR-V, {} in Rust",
                rust.name, rust.size
            ));
        }
    }
    mismatches
}

#[test]
fn shared_structs_match_their_rust_types_member_by_member() {
    let layouts = shared_layouts();
    let mut findings = Findings::default();
    let mut seen = BTreeSet::new();
    for (file, module) in modules() {
        for (&id, ty) in &module.types {
            let Type::Struct { members } = ty else {
                continue;
            };
            let Some(rust) = layouts.iter().find(|l| l.name == module.name(id)) else {
                continue;
            };
            // glslang also emits an undecorated copy for function-local values.
            let laid_out = (0..members.len() as u32)
                .all(|m| module.member_decoration(id, m, reader::OFFSET).is_some());
            if !laid_out {
                continue;
            }
            seen.insert(rust.name);
            for mismatch in compare_struct(module, id, rust) {
                findings.add(file, mismatch);
            }
        }
    }
    for (file, module) in modules() {
        for variable in &module.variables {
            let Some(Type::Pointer { pointee, .. }) = module.types.get(&variable.pointer) else {
                continue;
            };
            let block = module.name(*pointee);
            if variable.storage == reader::PUSH_CONSTANT && block != "PushConstants" {
                findings.add(file, format!("push constants `{block}`, not PushConstants"));
            }
        }
    }
    for (name, texels, fields) in TEXEL_RECORDS {
        let Some(rust) = layouts.iter().find(|l| l.name == name) else {
            findings.add_overall(format!("{name} is read as texels but has no Rust layout"));
            continue;
        };
        seen.insert(rust.name);
        let read: Vec<(&str, usize)> = rust.fields.iter().map(|f| (f.name, f.offset)).collect();
        if read != fields || rust.size != texels * 16 {
            findings.add_overall(format!(
                "{name}: Rust has {read:?} in {} bytes, load_instance reads {fields:?} from \
                 {texels} texels",
                rust.size
            ));
        }
    }
    for layout in &layouts {
        if !seen.contains(layout.name) {
            findings.add_overall(format!("no shader declares {} with a layout", layout.name));
        }
    }
    findings.assert_none("shared structs");
}

/// The names of the structs and blocks `gpu_layout.glsl` declares.
fn glsl_layout_names() -> Vec<&'static str> {
    GPU_LAYOUT_GLSL
        .lines()
        .filter_map(|line| {
            let line = line.trim_start();
            let declared = match line.strip_prefix("struct ") {
                Some(rest) => rest,
                None if line.starts_with("layout(") && !line.contains("constant_id") => {
                    let (_, rest) = line
                        .split_once(" uniform ")
                        .or(line.split_once(" buffer "))?;
                    rest
                }
                None => return None,
            };
            declared
                .split(|c: char| !c.is_alphanumeric() && c != '_')
                .next()
        })
        .collect()
}

#[test]
fn every_struct_of_gpu_layout_glsl_has_a_rust_mirror() {
    let names = glsl_layout_names();
    let layouts = shared_layouts();
    for expected in [
        "PushConstants",
        "Instance",
        "CompactInstance",
        "IndirectDraw",
    ] {
        assert!(
            names.contains(&expected),
            "{expected} not found in {names:?}"
        );
    }
    let unmirrored: Vec<_> = names
        .iter()
        .filter(|name| !layouts.iter().any(|l| l.name == **name))
        .collect();
    assert!(
        unmirrored.is_empty(),
        "gpu_layout.glsl declares {unmirrored:?} without a Rust type in the mirror's table \
         (src/spirv_mirror/rust_layouts.rs)"
    );
}

/// Compares one specialization constant with the Rust field of the same name.
fn compare_spec_constant(module: &Module, id: u32, constant: &Constant) -> Option<String> {
    let name = module.name(id);
    let spec_id = module.decoration(id, reader::SPEC_ID)?;
    let fields = spec_constant_fields();
    let Some(field) = fields.fields.iter().find(|f| f.name.to_uppercase() == name) else {
        return Some(format!(
            "{name} (SpecId {spec_id}) has no SpecConstants field"
        ));
    };
    let entries = SpecConstants::map_entries();
    let Some(entry) = entries.iter().find(|e| e.offset as usize == field.offset) else {
        return Some(format!("SpecConstants::{} has no map entry", field.name));
    };
    let defaults = SpecConstants::default();
    let bytes = bytemuck::bytes_of(&defaults);
    let default = u32::from_ne_bytes(bytes[field.offset..field.offset + 4].try_into().ok()?);
    let width = module.size_of(constant.ty);
    if entry.constant_id != spec_id
        || width != Some(entry.size as u32)
        || field.size != entry.size
        || default != constant.value
    {
        return Some(format!(
            "{name}: SpecId {spec_id}, {width:?} bytes, default {} in SPIR-V; constant_id {}, \
             {} bytes (field {}), default {default} in Rust",
            constant.value, entry.constant_id, entry.size, field.size
        ));
    }
    None
}

#[test]
fn specialization_constants_match_by_name_id_width_and_default() {
    let mut findings = Findings::default();
    let mut seen = BTreeSet::new();
    for (file, module) in modules() {
        for (&id, constant) in &module.constants {
            if !constant.spec || module.decoration(id, reader::SPEC_ID).is_none() {
                continue;
            }
            seen.insert(module.name(id).to_owned());
            if let Some(mismatch) = compare_spec_constant(module, id, constant) {
                findings.add(file, mismatch);
            }
        }
    }
    // Every Rust constant is one some shader reads.
    for field in &spec_constant_fields().fields {
        if !seen.contains(&field.name.to_uppercase()) {
            findings.add_overall(format!("no shader declares {}", field.name.to_uppercase()));
        }
    }
    findings.assert_none("specialization constants");
}

#[test]
fn spec_constant_ids_cover_every_field_once() {
    let fields = spec_constant_fields();
    let entries = SpecConstants::map_entries();
    assert_eq!(
        entries.len(),
        fields.fields.len(),
        "one map entry per field"
    );
    let offsets: BTreeSet<_> = entries.iter().map(|e| e.offset as usize).collect();
    let ids: BTreeSet<_> = entries.iter().map(|e| e.constant_id).collect();
    assert_eq!(offsets.len(), entries.len(), "two entries share a field");
    assert_eq!(ids.len(), entries.len(), "two entries share a constant_id");
    for field in &fields.fields {
        assert!(
            offsets.contains(&field.offset),
            "{} has no entry",
            field.name
        );
    }
}

#[test]
fn descriptor_bindings_match_the_binding_table() {
    let mut findings = Findings::default();
    let mut seen = BTreeSet::new();
    for (file, module) in modules() {
        if SAMPLE_ZERO_MODULES.contains(file) {
            continue; // its own set: `sample_zero_bindings_match_its_set_layout`
        }
        let stage = stage(file, module);
        for variable in &module.variables {
            let Some(number) = module.decoration(variable.id, reader::BINDING) else {
                continue;
            };
            let set = module.decoration(variable.id, reader::DESCRIPTOR_SET);
            if set == Some(1) && TRACED_MODULES.contains(file) {
                continue; // the traced path's own set: its structure and boxes (`traced.rs`)
            }
            let block = match module.types.get(&variable.pointer) {
                Some(Type::Pointer { pointee, .. }) => module.name(*pointee),
                _ => "",
            };
            if set != Some(0) {
                findings.add(
                    file,
                    format!("{block} (binding {number}) is in set {set:?}"),
                );
            }
            if variable.storage == reader::UNIFORM_CONSTANT {
                // A texel view: the binding and name of the set layout's.
                let name = module.name(variable.id);
                let Some((_, _, stages, kind)) = texel_views()
                    .into_iter()
                    .find(|(n, v, _, _)| *n == number && *v == name)
                else {
                    findings.add(
                        file,
                        format!("{name} (binding {number}) is not a texel view of the set layout"),
                    );
                    continue;
                };
                // A buffer image, sampled for a uniform texel buffer, storage for a storage one.
                let image = match module.types.get(&variable.pointer) {
                    Some(Type::Pointer { pointee, .. }) => module.types.get(pointee),
                    _ => None,
                };
                let sampled = if kind == vk::DescriptorType::STORAGE_TEXEL_BUFFER {
                    reader::SAMPLED_AS_STORAGE
                } else {
                    reader::SAMPLED_WITH_SAMPLER
                };
                let dim = reader::DIM_BUFFER;
                if image != Some(&Type::Image { dim, sampled }) {
                    findings.add(
                        file,
                        format!("{name} (binding {number}) is {image:?}, not a {kind:?}"),
                    );
                }
                if module.accessed.contains(&variable.id) {
                    seen.insert(number);
                    if !stages.contains(stage) {
                        findings.add(file, format!("{name} is read by {stage:?}"));
                    }
                }
                continue;
            }
            if variable.storage != reader::STORAGE_BUFFER {
                let class = variable.storage;
                findings.add(
                    file,
                    format!("{block} (binding {number}) has storage class {class}, not a buffer"),
                );
            }
            let Some(binding) = Binding::ALL.into_iter().find(|b| *b as u32 == number) else {
                findings.add(
                    file,
                    format!("{block} uses binding {number}, not in Binding"),
                );
                continue;
            };
            if binding.descriptor_type() != vk::DescriptorType::STORAGE_BUFFER {
                findings.add(
                    file,
                    format!("{block} reads Binding::{binding:?} as a storage buffer"),
                );
            }
            let named = format!("{binding:?}") == block || OTHER_VIEWS.contains(&(binding, block));
            if !named {
                findings.add(
                    file,
                    format!("binding {number} is the block {block}, Binding::{binding:?} in Rust"),
                );
            }
            if !module.accessed.contains(&variable.id) {
                continue; // declared by a shared include, never touched by this stage
            }
            seen.insert(number);
            if !binding.stages().contains(stage) {
                let stages = binding.stages();
                findings.add(
                    file,
                    format!("Binding::{binding:?}'s stages {stages:?} leave out {stage:?}"),
                );
            }
        }
    }
    for binding in Binding::ALL {
        // The tiled splat's lists have users only among the `research` shaders.
        let built = cfg!(feature = "research") || binding != Binding::TileLists;
        if built && !seen.contains(&(binding as u32)) {
            findings.add_overall(format!("no shader uses Binding::{binding:?}"));
        }
    }
    for view in TEXEL_VIEWS {
        if !seen.contains(&view.binding) {
            findings.add_overall(format!(
                "no shader uses binding {}'s texel view",
                view.binding
            ));
        }
    }
    findings.assert_none("descriptor bindings");
}

/// The fetch of sample 0 reads its texture at `TEXTURE_BINDING` and writes the block
/// `SampleZeroWords` at `WORDS_BINDING`, both in set 0, as its set layout says.
#[cfg(feature = "offscreen")]
#[test]
fn sample_zero_bindings_match_its_set_layout() {
    use crate::offscreen::sample_zero::{TEXTURE_BINDING, WORDS_BINDING};
    let mut findings = Findings::default();
    for file in SAMPLE_ZERO_MODULES {
        let Some(module) = modules().get(file) else {
            findings.add(file, "not built".into());
            continue;
        };
        let mut found = BTreeMap::new();
        for variable in &module.variables {
            let Some(number) = module.decoration(variable.id, reader::BINDING) else {
                continue;
            };
            if module.decoration(variable.id, reader::DESCRIPTOR_SET) != Some(0) {
                findings.add(file, format!("binding {number} is not in set 0"));
            }
            let block = match module.types.get(&variable.pointer) {
                Some(Type::Pointer { pointee, .. }) => module.name(*pointee),
                _ => "",
            };
            found.insert(number, (variable.storage, block));
        }
        let expected = BTreeMap::from([
            (TEXTURE_BINDING, (reader::UNIFORM_CONSTANT, "")),
            (WORDS_BINDING, (reader::STORAGE_BUFFER, "SampleZeroWords")),
        ]);
        if found != expected {
            findings.add(file, format!("bindings {found:?}, set layout {expected:?}"));
        }
    }
    findings.assert_none("sample-zero bindings");
}

#[test]
fn binding_table_numbers_each_binding_once_in_order() {
    for (index, binding) in Binding::ALL.into_iter().enumerate() {
        assert_eq!(
            binding as usize, index,
            "Binding::ALL out of order at {binding:?}"
        );
    }
}

/// A compute module's workgroup size, from `LocalSize` or `LocalSizeId` (whose ids name
/// constants or specialization constants).
fn workgroup_size(module: &Module) -> Option<[u64; 3]> {
    let mode = module
        .execution_modes
        .iter()
        .find(|m| matches!(m.mode, reader::LOCAL_SIZE | reader::LOCAL_SIZE_ID))?;
    let mut size = [0; 3];
    for (axis, &operand) in size.iter_mut().zip(mode.operands.iter()) {
        *axis = if mode.ids {
            module.constants.get(&operand)?.value as u64
        } else {
            operand as u64
        };
    }
    (mode.operands.len() == 3).then_some(size)
}

#[test]
fn compute_workgroup_sizes_match_the_dispatch_constants() {
    let expected = dispatch_group_sizes();
    let mut findings = Findings::default();
    let mut checked = 0;
    for (file, module) in modules() {
        if stage(file, module) != vk::ShaderStageFlags::COMPUTE {
            continue;
        }
        let Some((_, rust)) = expected.iter().find(|(name, _)| name == file) else {
            findings.add(file, "no dispatch constant in the mirror's table".into());
            continue;
        };
        checked += 1;
        let spirv = workgroup_size(module);
        if spirv != Some(*rust) {
            findings.add(
                file,
                format!("workgroup {spirv:?} in SPIR-V, {rust:?} in Rust"),
            );
        }
    }
    if checked != expected.len() {
        let listed = expected.len();
        findings.add_overall(format!(
            "{checked} of the {listed} listed compute shaders built"
        ));
    }
    findings.assert_none("workgroup sizes");
}
