//! What a SPIR-V module binds, read from the module itself (as niagara and kajiya derive their
//! layouts): each descriptor's set, binding and type, and the module's stage. A pipeline's set
//! layouts are the union of its stages' (`merge`), so a shader's declarations are the one place a
//! binding is written down: no hand-kept list to keep in step with the GLSL.
//!
//! Each descriptor also carries its name as the GLSL wrote it: a block's interface name
//! (`buffer Visible { … }` is `Visible`), an opaque variable's own (`uniform usamplerBuffer
//! visible_texels`). Owners give resources by these names (`SetLayout::write_named`), so no
//! number table sits between a shader and the Rust that feeds it.
//!
//! Only what the entry point uses counts: the descriptors its function and the functions it calls
//! (transitively) refer to, so a header that declares twenty bindings costs a shader only the ones
//! it reads. (glslang lists every declared global in the entry point's interface, used or not.)

use std::collections::BTreeMap;

use ash::vk;

use crate::error::{Error, Result};
use crate::vk::descriptor::Binding;

/// One descriptor a module declares.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Descriptor {
    /// `layout(set = …)`.
    pub set: u32,
    /// `layout(binding = …)`.
    pub binding: u32,
    /// Its type.
    pub kind: vk::DescriptorType,
    /// Its name: a block's interface name, else the variable's ("" when the module has none).
    pub name: String,
}

/// A module's stage and the descriptors its entry point uses, sorted by (set, binding).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Reflection {
    /// The entry point's stage.
    pub stage: vk::ShaderStageFlags,
    /// The descriptors.
    pub descriptors: Vec<Descriptor>,
}

const MAGIC: u32 = 0x0723_0203;
/// A debug line: its literals (file, line, column) are not ids, and a line number equal to a
/// variable's id would count it as used.
const OP_LINE: u32 = 8;
const OP_NAME: u32 = 5;
const OP_ENTRY_POINT: u32 = 15;
const OP_FUNCTION: u32 = 54;
const OP_FUNCTION_END: u32 = 56;
const OP_TYPE_IMAGE: u32 = 25;
const OP_TYPE_SAMPLER: u32 = 26;
const OP_TYPE_SAMPLED_IMAGE: u32 = 27;
const OP_TYPE_ARRAY: u32 = 28;
const OP_TYPE_RUNTIME_ARRAY: u32 = 29;
const OP_TYPE_STRUCT: u32 = 30;
const OP_TYPE_POINTER: u32 = 32;
const OP_VARIABLE: u32 = 59;
const OP_DECORATE: u32 = 71;
const OP_SPEC_CONSTANT_TRUE: u32 = 48;
const OP_SPEC_CONSTANT_FALSE: u32 = 49;
const OP_SPEC_CONSTANT: u32 = 50;
const DECORATION_SPEC_ID: u32 = 1;
const OP_TYPE_ACCELERATION_STRUCTURE: u32 = 5341;
const DECORATION_BLOCK: u32 = 2;
const DECORATION_BUFFER_BLOCK: u32 = 3;
const DECORATION_BINDING: u32 = 33;
const DECORATION_DESCRIPTOR_SET: u32 = 34;
const STORAGE_UNIFORM_CONSTANT: u32 = 0;
const STORAGE_UNIFORM: u32 = 2;
const STORAGE_STORAGE_BUFFER: u32 = 12;
const DIM_BUFFER: u32 = 5;
const DIM_SUBPASS_DATA: u32 = 6;

/// The types a descriptor's variable may point at.
#[derive(Clone, Copy)]
enum Type {
    Image {
        dim: u32,
        sampled: u32,
    },
    Sampler,
    /// Of the image type of this id.
    SampledImage(u32),
    Array,
    Struct,
    /// To the type of this id.
    Pointer(u32),
    AccelerationStructure,
}

/// What `reflect` reads from a module's instructions.
#[derive(Default)]
struct Module {
    stage: Option<vk::ShaderStageFlags>,
    /// The entry point's function.
    entry: u32,
    /// Every operand word of each function's instructions, by function id: the variables it
    /// refers to and the functions it calls are among them.
    functions: BTreeMap<u32, Vec<u32>>,
    types: BTreeMap<u32, Type>,
    sets: BTreeMap<u32, u32>,
    bindings: BTreeMap<u32, u32>,
    /// Struct id to `Block` or `BufferBlock`.
    blocks: BTreeMap<u32, u32>,
    /// (id, pointer type, storage class).
    variables: Vec<(u32, u32, u32)>,
    /// `OpName`s by id, the first an id is given: glslang names a specialization constant where
    /// it is declared, and again after a `const` initialised from it (`const uint segments =
    /// SEGMENTS;` in blade.vert shares its id).
    names: BTreeMap<u32, String>,
    /// `SpecId` decorations: constant id to `constant_id`.
    spec_ids: BTreeMap<u32, u32>,
    /// The scalar specialization constants (`OpSpecConstant*`) by id.
    spec_constants: Vec<u32>,
}

/// Read the instructions `reflect` needs.
fn parse(spirv: &[u8]) -> std::result::Result<Module, String> {
    if !spirv.len().is_multiple_of(4) || spirv.len() < 20 {
        return Err("not a SPIR-V module".into());
    }
    let words: Vec<u32> = spirv.chunks_exact(4).map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect();
    if words[0] != MAGIC {
        return Err("not a little-endian SPIR-V module".into());
    }
    let mut m = Module::default();
    let mut function = None;
    let mut at = 5;
    while at < words.len() {
        let count = (words[at] >> 16) as usize;
        if count == 0 || at + count > words.len() {
            return Err("truncated instruction".into());
        }
        let (op, args) = (words[at] & 0xffff, &words[at + 1..at + count]);
        at += count;
        match (op, function) {
            (OP_FUNCTION, _) if args.len() >= 2 => function = Some(args[1]),
            (OP_FUNCTION_END, _) => function = None,
            (OP_LINE, _) => {}
            (_, Some(f)) => m.functions.entry(f).or_default().extend_from_slice(args),
            _ => {}
        }
        let Some(&id) = args.first() else { continue };
        match op {
            OP_NAME => {
                m.names.entry(id).or_insert_with(|| literal_string(&args[1..]));
            }
            OP_ENTRY_POINT if m.stage.is_some() => return Err("more than one entry point".into()),
            OP_ENTRY_POINT => {
                let (stage, entry) = entry_point(args)?;
                (m.stage, m.entry) = (Some(stage), entry);
            }
            OP_DECORATE => match (args.get(1).copied(), args.get(2).copied()) {
                (Some(DECORATION_DESCRIPTOR_SET), Some(set)) => {
                    m.sets.insert(id, set);
                }
                (Some(DECORATION_BINDING), Some(binding)) => {
                    m.bindings.insert(id, binding);
                }
                (Some(d @ (DECORATION_BLOCK | DECORATION_BUFFER_BLOCK)), _) => {
                    m.blocks.insert(id, d);
                }
                (Some(DECORATION_SPEC_ID), Some(spec)) => {
                    m.spec_ids.insert(id, spec);
                }
                _ => {}
            },
            OP_TYPE_IMAGE if args.len() >= 7 => {
                m.types.insert(id, Type::Image { dim: args[2], sampled: args[6] });
            }
            OP_TYPE_SAMPLER => {
                m.types.insert(id, Type::Sampler);
            }
            OP_TYPE_SAMPLED_IMAGE => {
                m.types.insert(id, Type::SampledImage(args.get(1).copied().unwrap_or(0)));
            }
            OP_TYPE_ARRAY | OP_TYPE_RUNTIME_ARRAY => {
                m.types.insert(id, Type::Array);
            }
            OP_TYPE_STRUCT => {
                m.types.insert(id, Type::Struct);
            }
            OP_TYPE_POINTER if args.len() >= 3 => {
                m.types.insert(id, Type::Pointer(args[2]));
            }
            OP_TYPE_ACCELERATION_STRUCTURE => {
                m.types.insert(id, Type::AccelerationStructure);
            }
            OP_VARIABLE if args.len() >= 3 => m.variables.push((args[1], id, args[2])),
            OP_SPEC_CONSTANT_TRUE | OP_SPEC_CONSTANT_FALSE | OP_SPEC_CONSTANT if args.len() >= 2 => {
                m.spec_constants.push(args[1])
            }
            _ => {}
        }
    }
    Ok(m)
}

/// A SPIR-V literal string: UTF-8 bytes packed little-endian in words, ending with a NUL.
fn literal_string(words: &[u32]) -> String {
    let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).take_while(|&b| b != 0).collect();
    String::from_utf8_lossy(&bytes).into_owned()
}

/// An `OpEntryPoint`'s stage and function (its arguments: execution model, function id, name,
/// interface ids).
fn entry_point(args: &[u32]) -> std::result::Result<(vk::ShaderStageFlags, u32), String> {
    let stage = match args[0] {
        0 => vk::ShaderStageFlags::VERTEX,
        4 => vk::ShaderStageFlags::FRAGMENT,
        5 => vk::ShaderStageFlags::COMPUTE,
        model => return Err(format!("execution model {model}")),
    };
    let function = *args.get(1).ok_or("an entry point without a function")?;
    Ok((stage, function))
}

impl Module {
    /// Every id the entry point's function and the functions it calls refer to.
    fn used(&self) -> std::collections::BTreeSet<u32> {
        let mut reached = std::collections::BTreeSet::from([self.entry]);
        let mut queue = vec![self.entry];
        let mut used = std::collections::BTreeSet::new();
        while let Some(f) = queue.pop() {
            for &word in self.functions.get(&f).into_iter().flatten() {
                used.insert(word);
                if self.functions.contains_key(&word) && reached.insert(word) {
                    queue.push(word);
                }
            }
        }
        used
    }

    /// The name of variable `id` of pointer type `pointer`: its block's interface name when it
    /// points at a block, else its own.
    fn name(&self, id: u32, pointer: u32) -> String {
        let pointee = match self.types.get(&pointer) {
            Some(&Type::Pointer(pointee)) => Some(pointee),
            _ => None,
        };
        match pointee.filter(|p| self.blocks.contains_key(p)) {
            Some(block) => self.names.get(&block),
            None => self.names.get(&id),
        }
        .cloned()
        .unwrap_or_default()
    }

    /// The descriptor type of a variable of pointer type `pointer` in storage class `class`.
    fn kind(&self, pointer: u32, class: u32) -> std::result::Result<vk::DescriptorType, String> {
        use vk::DescriptorType as T;
        let Some(&Type::Pointer(pointee)) = self.types.get(&pointer) else {
            return Err("not a pointer".into());
        };
        Ok(match (class, self.types.get(&pointee)) {
            (_, Some(Type::Array)) => {
                return Err("arrays of descriptors are not supported (one descriptor per binding)".into())
            }
            (STORAGE_STORAGE_BUFFER, _) => T::STORAGE_BUFFER,
            (STORAGE_UNIFORM, Some(Type::Struct)) => match self.blocks.get(&pointee) {
                Some(&DECORATION_BUFFER_BLOCK) => T::STORAGE_BUFFER,
                Some(_) => T::UNIFORM_BUFFER,
                None => return Err("a uniform struct without Block".into()),
            },
            (STORAGE_UNIFORM_CONSTANT, Some(&Type::Image { dim, sampled })) => match (dim, sampled) {
                (DIM_BUFFER, 1) => T::UNIFORM_TEXEL_BUFFER,
                (DIM_BUFFER, _) => T::STORAGE_TEXEL_BUFFER,
                (DIM_SUBPASS_DATA, _) => T::INPUT_ATTACHMENT,
                (_, 1) => T::SAMPLED_IMAGE,
                _ => T::STORAGE_IMAGE,
            },
            (STORAGE_UNIFORM_CONSTANT, Some(Type::SampledImage(image))) => match self.types.get(image) {
                // `samplerBuffer`: a uniform texel buffer.
                Some(Type::Image { dim: DIM_BUFFER, .. }) => T::UNIFORM_TEXEL_BUFFER,
                _ => T::COMBINED_IMAGE_SAMPLER,
            },
            (STORAGE_UNIFORM_CONSTANT, Some(Type::Sampler)) => T::SAMPLER,
            (STORAGE_UNIFORM_CONSTANT, Some(Type::AccelerationStructure)) => T::ACCELERATION_STRUCTURE_KHR,
            _ => return Err(format!("storage class {class} of an unknown descriptor type")),
        })
    }
}

/// Reflect `spirv` (one entry point); `name` names it in errors.
pub fn reflect(name: &str, spirv: &[u8]) -> Result<Reflection> {
    let bad = |why: String| Error::Internal(format!("{name}: SPIR-V reflection: {why}"));
    let module = parse(spirv).map_err(bad)?;
    let stage = module.stage.ok_or_else(|| bad("no entry point".into()))?;
    let used = module.used();
    let mut descriptors = Vec::new();
    for &(id, pointer, class) in &module.variables {
        let (Some(&set), Some(&binding)) = (module.sets.get(&id), module.bindings.get(&id)) else {
            continue;
        };
        if used.contains(&id) {
            let kind = module.kind(pointer, class).map_err(|why| bad(format!("set {set} binding {binding}: {why}")))?;
            descriptors.push(Descriptor { set, binding, kind, name: module.name(id, pointer) });
        }
    }
    descriptors.sort_by_key(|d| (d.set, d.binding));
    Ok(Reflection { stage, descriptors })
}

/// The specialization constants `spirv` declares, as `(constant_id, name)` sorted by id: the
/// name its GLSL gives it (`layout(constant_id = …) const uint SEGMENTS` is `SEGMENTS`), so a
/// pipeline fills them by name and no id is kept in Rust. A constant with no name of its own (the
/// workgroup size of `local_size_x_id`) is named after the constant that shares its id, and is an
/// error when none does; `name` names the module in errors.
pub fn spec_constants(name: &str, spirv: &[u8]) -> Result<Vec<(u32, String)>> {
    let bad = |why: String| Error::Internal(format!("{name}: SPIR-V reflection: {why}"));
    let module = parse(spirv).map_err(bad)?;
    let mut named: BTreeMap<u32, String> = BTreeMap::new();
    let mut unnamed = Vec::new();
    for id in &module.spec_constants {
        let Some(&spec) = module.spec_ids.get(id) else { continue };
        match module.names.get(id).filter(|n| !n.is_empty()) {
            Some(n) => match named.insert(spec, n.clone()) {
                Some(other) if other != *n => {
                    return Err(bad(format!("constant_id {spec} is both `{other}` and `{n}`")));
                }
                _ => {}
            },
            None => unnamed.push(spec),
        }
    }
    if let Some(spec) = unnamed.into_iter().find(|spec| !named.contains_key(spec)) {
        return Err(bad(format!("constant_id {spec} has no name (give a named constant that id too)")));
    }
    Ok(named.into_iter().collect())
}

/// The bindings of each set that `shaders` (one pipeline's stages, or every pipeline sharing a
/// layout) use together, by set number: a binding's stages are those that use it. Two shaders
/// giving one binding different types are an error naming both.
pub fn merge(shaders: &[(&str, &[u8])]) -> Result<BTreeMap<u32, Vec<Binding>>> {
    Ok(merge_named(shaders)?
        .into_iter()
        .map(|(set, bindings)| (set, bindings.into_iter().map(|(b, _)| b).collect()))
        .collect())
}

/// `merge`, with each binding's name (`Descriptor::name`). Two shaders giving one binding
/// different names are an error too: a binding is one resource.
pub fn merge_named(shaders: &[(&str, &[u8])]) -> Result<BTreeMap<u32, Vec<(Binding, String)>>> {
    merge_sets(shaders, &|_| true)
}

/// `merge_named` of the sets `keep` accepts only: shaders that share some sets (the scene's) and
/// number another each for itself (a pass's own set) merge the shared ones.
pub fn merge_sets(
    shaders: &[(&str, &[u8])],
    keep: &dyn Fn(u32) -> bool,
) -> Result<BTreeMap<u32, Vec<(Binding, String)>>> {
    let mut sets: BTreeMap<u32, Vec<(Binding, &str, String)>> = BTreeMap::new();
    for &(name, spirv) in shaders {
        let reflection = reflect(name, spirv)?;
        for d in reflection.descriptors.into_iter().filter(|d| keep(d.set)) {
            let set = sets.entry(d.set).or_default();
            match set.iter_mut().find(|(b, _, _)| b.binding == d.binding) {
                Some((b, _, named)) if b.kind == d.kind && *named == d.name => b.stages |= reflection.stage,
                Some((b, first, named)) => {
                    return Err(Error::Internal(format!(
                        "set {} binding {}: {first} binds {:?} `{named}`, {name} binds {:?} `{}`",
                        d.set, d.binding, b.kind, d.kind, d.name
                    )))
                }
                None => {
                    let binding = Binding { binding: d.binding, kind: d.kind, stages: reflection.stage };
                    set.push((binding, name, d.name))
                }
            }
        }
    }
    Ok(sets
        .into_iter()
        .map(|(set, mut bindings)| {
            bindings.sort_by_key(|(b, _, _)| b.binding);
            (set, bindings.into_iter().map(|(b, _, named)| (b, named)).collect())
        })
        .collect())
}
