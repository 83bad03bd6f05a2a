//! The event loop as SPIR-V whose floating-point operations the driver may not fuse or
//! reorder: naga's output for the WGSL source, written with the options wgpu's Vulkan
//! backend uses, then every float `+ − × ÷` decorated `NoContraction`.
//!
//! # Why
//! WGSL lets an implementation contract `a * b + c` into one fused multiply-add, and
//! naga's SPIR-V carries no decoration that forbids it; NVIDIA's driver fuses, Mesa's
//! (lavapipe) re-associates sums. Either way the GPU's f64 differs from the Rust twin's in
//! the last bits, and an event-based simulation turns last bits into different runs (a
//! break parts from the CPU's sequence after a few dozen events). `NoContraction` on every
//! arithmetic result is SPIR-V's way to say "round each operation as written" (Vulkan
//! maps it to GLSL's `precise`; Mesa's NIR marks the instructions exact, so its
//! algebraic passes leave them alone). With it, and with the Rust twin computing the same
//! operations in the same order (the transcendental functions as
//! [`crate::model::fmath`]'s polynomials, dot and cross products written out), the f64
//! event loop gives the CPU's runs bit for bit on a device whose f64 `+ − × ÷ sqrt` are
//! IEEE's (correctly rounded) and whose `fma` is fused.
//!
//! # Method
//! SPIR-V's logical layout puts decorations (`OpDecorate`) after the debug names and
//! before the types; [`forbid_contraction`] collects the result ids of the float
//! arithmetic opcodes in the functions and inserts one `OpDecorate id NoContraction` each
//! at the end of the annotation section. The module goes to the driver through wgpu's
//! SPIR-V passthrough (`Features::PASSTHROUGH_SHADERS`, Vulkan only), so its overrides
//! are resolved here ([`naga::back::pipeline_constants::process_overrides`]) and its
//! runtime checks are naga's as wgpu writes them: indices clamped (`Restrict`) for
//! workgroup arrays and buffers alike, loops bounded, workgroup memory zeroed by the
//! shader itself (`Polyfill`), so the module is safe on any device without asking which
//! robustness features it has.
//!
//! Source: the SPIR-V specification 1.6, §2.4 (logical layout), §3.32.2 (`NoContraction`,
//! decoration 42), §3.42 (opcodes); the Vulkan specification, "Precision and Operation of
//! SPIR-V Instructions".

/// `OpDecorate`.
const OP_DECORATE: u32 = 71;
/// `OpFunction`: the first function ends the module's declarations.
const OP_FUNCTION: u32 = 54;
/// `NoContraction`.
const NO_CONTRACTION: u32 = 42;

/// The annotation opcodes: `OpDecorate`, `OpMemberDecorate`, `OpDecorationGroup`,
/// `OpGroupDecorate`, `OpGroupMemberDecorate`, `OpDecorateId`, `OpDecorateString`,
/// `OpMemberDecorateString`.
const ANNOTATIONS: [u32; 8] = [71, 72, 73, 74, 75, 332, 5632, 5633];

/// The float arithmetic opcodes whose result `NoContraction` applies to: `OpFNegate`,
/// `OpFAdd`, `OpFSub`, `OpFMul`, `OpFDiv`, `OpFRem`, `OpFMod`, `OpVectorTimesScalar`,
/// `OpMatrixTimesScalar`, `OpVectorTimesMatrix`, `OpMatrixTimesVector`,
/// `OpMatrixTimesMatrix`, `OpOuterProduct`, `OpDot`.
const FLOAT_ARITHMETIC: [u32; 14] = [
    127, 129, 131, 133, 136, 140, 141, 142, 143, 144, 145, 146, 147, 148,
];

/// The first word of a SPIR-V instruction: its word count and opcode.
fn instruction(word_count: u32, opcode: u32) -> u32 {
    (word_count << 16) | opcode
}

/// Decorates the result of every float arithmetic instruction of `words` (a SPIR-V
/// module) `NoContraction`, unless it already is; returns how many it decorated. A module
/// that is not SPIR-V (bad magic number, an instruction running past the end) is an
/// error, and `words` is left as it was.
pub fn forbid_contraction(words: &mut Vec<u32>) -> Result<usize, String> {
    const MAGIC: u32 = 0x0723_0203;
    if words.len() < 5 || words[0] != MAGIC {
        return Err("not a SPIR-V module (no magic number)".into());
    }
    let mut at = 5;
    let mut insert_at = None;
    let mut first_function = None;
    let mut results = Vec::new();
    let mut decorated = std::collections::HashSet::new();
    while at < words.len() {
        let (count, opcode) = ((words[at] >> 16) as usize, words[at] & 0xffff);
        if count == 0 || at + count > words.len() {
            return Err(format!(
                "instruction at word {at} runs past the module's end"
            ));
        }
        if ANNOTATIONS.contains(&opcode) {
            insert_at = Some(at + count);
            if opcode == OP_DECORATE && count == 3 && words[at + 2] == NO_CONTRACTION {
                decorated.insert(words[at + 1]);
            }
        }
        if opcode == OP_FUNCTION && first_function.is_none() {
            first_function = Some(at);
        }
        if first_function.is_some() && FLOAT_ARITHMETIC.contains(&opcode) && count >= 3 {
            results.push(words[at + 2]);
        }
        at += count;
    }
    // naga always writes decorations (bindings, block layouts); a module without any is
    // not one of its, and is refused rather than guessed at
    let Some(insert_at) = insert_at else {
        return Err("no annotation section to add the decorations to".into());
    };
    results.retain(|id| !decorated.contains(id));
    let added: Vec<u32> = results
        .iter()
        .flat_map(|&id| [instruction(3, OP_DECORATE), id, NO_CONTRACTION])
        .collect();
    words.splice(insert_at..insert_at, added);
    Ok(results.len())
}

/// A buffer binding of an entry point: its number and how the shader declares it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Binding {
    /// `@binding(n)` (group 0).
    pub binding: u32,
    /// `var<uniform>`, else `var<storage, …>`.
    pub uniform: bool,
    /// `var<storage, read>`.
    pub read_only: bool,
}

/// One entry point as exact SPIR-V, with the bindings it uses (what wgpu's reflection
/// would have found: a passthrough module has none).
#[derive(Clone, Debug)]
pub struct ExactShader {
    /// The SPIR-V words.
    pub words: Vec<u32>,
    /// The group-0 buffer bindings the entry point uses, in binding order.
    pub bindings: Vec<Binding>,
}

/// The SPIR-V of `entry` in the WGSL `source` with its overrides set to `constants`,
/// written as described in the module docs (SPIR-V 1.3: Vulkan 1.1; `checked` false
/// leaves out the index clamps and loop bounding, for measuring what they cost), every
/// float operation `NoContraction`. An error says what naga refused.
pub fn event_loop_spirv(
    source: &str,
    entry: &str,
    constants: &[(&str, f64)],
    checked: bool,
) -> Result<Vec<u32>, String> {
    exact_shader(source, entry, constants, checked).map(|s| s.words)
}

/// [`event_loop_spirv`] with the entry point's bindings.
pub fn exact_shader(
    source: &str,
    entry: &str,
    constants: &[(&str, f64)],
    checked: bool,
) -> Result<ExactShader, String> {
    let module = naga::front::wgsl::parse_str(source).map_err(|e| e.emit_to_string(source))?;
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .map_err(|e| e.emit_to_string(source))?;
    let constants: naga::back::PipelineConstants =
        constants.iter().map(|&(k, v)| (k.to_string(), v)).collect();
    let (module, info) = naga::back::pipeline_constants::process_overrides(
        &module,
        &info,
        Some((naga::ShaderStage::Compute, entry)),
        &constants,
    )
    .map_err(|e| e.to_string())?;
    let policy = match checked {
        true => naga::proc::BoundsCheckPolicy::Restrict,
        false => naga::proc::BoundsCheckPolicy::Unchecked,
    };
    let mut options = naga::back::spv::Options {
        lang_version: (1, 3),
        // wgpu's flags for a compute shader outside its debug mode (no debug names)
        flags: naga::back::spv::WriterFlags::LABEL_VARYINGS,
        ..Default::default()
    };
    options.bounds_check_policies = naga::proc::BoundsCheckPolicies {
        index: policy,
        buffer: policy,
        image_load: policy,
        binding_array: naga::proc::BoundsCheckPolicy::Unchecked,
    };
    options.zero_initialize_workgroup_memory =
        naga::back::spv::ZeroInitializeWorkgroupMemoryMode::Polyfill;
    options.force_loop_bounding = checked;
    let index = module
        .entry_points
        .iter()
        .position(|e| e.name == entry)
        .ok_or_else(|| format!("no entry point {entry:?}"))?;
    let used = info.get_entry_point(index);
    let mut bindings: Vec<Binding> = module
        .global_variables
        .iter()
        .filter(|(handle, _)| !used[*handle].is_empty())
        .filter_map(|(_, var)| {
            let b = var.binding.as_ref()?;
            match var.space {
                naga::AddressSpace::Uniform => Some(Binding {
                    binding: b.binding,
                    uniform: true,
                    read_only: true,
                }),
                naga::AddressSpace::Storage { access } => Some(Binding {
                    binding: b.binding,
                    uniform: false,
                    read_only: !access.contains(naga::StorageAccess::STORE),
                }),
                _ => None,
            }
        })
        .collect();
    bindings.sort_by_key(|b| b.binding);
    options.binding_map = vulkan_bindings(&module, &bindings);
    let pipeline = naga::back::spv::PipelineOptions {
        shader_stage: naga::ShaderStage::Compute,
        entry_point: entry.into(),
    };
    let mut words = naga::back::spv::write_vec(&module, &info, &options, Some(&pipeline))
        .map_err(|e| e.to_string())?;
    forbid_contraction(&mut words)?;
    Ok(ExactShader { words, bindings })
}

/// Where each group-0 binding of `module` lies in the Vulkan descriptor set wgpu makes
/// for a layout of `used` (sorted by binding): wgpu's Vulkan backend numbers a layout's
/// descriptors 0, 1, 2, … in the order of their bindings (wgpu-hal's
/// `create_bind_group_layout`) and has naga write each shader's bindings so; a passthrough
/// module must be written the same way, or an entry point whose bindings have gaps (those
/// of `expand_tables`: 0, 3, 4, 5, 6) reads and writes the wrong buffers. A binding the
/// entry point does not use gets a number after those, so that none is shared.
fn vulkan_bindings(module: &naga::Module, used: &[Binding]) -> naga::back::spv::BindingMap {
    let mut map = naga::back::spv::BindingMap::new();
    let mut spare = used.len() as u32;
    for (_, var) in module.global_variables.iter() {
        let Some(b) = var.binding.as_ref() else {
            continue;
        };
        let at = match used
            .iter()
            .position(|u| u.binding == b.binding && b.group == 0)
        {
            Some(k) => k as u32,
            None => {
                spare += 1;
                spare - 1
            }
        };
        map.insert(
            *b,
            naga::back::spv::BindingInfo {
                descriptor_set: b.group,
                binding: at,
                binding_array_size: None,
            },
        );
    }
    map
}

/// Entry point `entry` of the WGSL `source` (overrides set to `constants`) as a compute
/// pipeline built from its exact SPIR-V ([`exact_shader`]) through wgpu's passthrough,
/// its bind-group layout given from the bindings it uses. The device must have been
/// opened with `Features::PASSTHROUGH_SHADERS` (Vulkan). Errors: what naga refused; the
/// driver's land in the caller's error scope.
pub fn exact_pipeline(
    device: &wgpu::Device,
    source: &str,
    entry: &str,
    constants: &[(&str, f64)],
) -> Result<wgpu::ComputePipeline, String> {
    let shader = exact_shader(source, entry, constants, true)?;
    let entries: Vec<wgpu::BindGroupLayoutEntry> = shader
        .bindings
        .iter()
        .map(|b| wgpu::BindGroupLayoutEntry {
            binding: b.binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: match b.uniform {
                    true => wgpu::BufferBindingType::Uniform,
                    false => wgpu::BufferBindingType::Storage {
                        read_only: b.read_only,
                    },
                },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        })
        .collect();
    // SAFETY: the words are naga's SPIR-V for the validated WGSL, written with its runtime
    // checks (indices clamped, loops bounded, workgroup memory zeroed) and only decorated
    // NoContraction; the layout declares exactly the bindings the entry point uses.
    let module = unsafe {
        device.create_shader_module_passthrough(wgpu::ShaderModuleDescriptorPassthrough {
            label: Some(entry),
            // the workgroup size is read by Metal only
            entry_points: vec![wgpu::PassthroughShaderEntryPoint {
                name: entry.into(),
                workgroup_size: (0, 0, 0),
            }]
            .into(),
            spirv: Some(shader.words.into()),
            ..Default::default()
        })
    };
    let bind_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(entry),
        entries: &entries,
    });
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(entry),
        bind_group_layouts: &[Some(&bind_layout)],
        immediate_size: 0,
    });
    Ok(
        device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(entry),
            layout: Some(&layout),
            module: &module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        }),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A one-line kernel with a multiply, an add and a subtract, as naga writes it.
    fn module() -> Vec<u32> {
        let source = "@group(0) @binding(0) var<storage, read_write> x: array<f32>;\n\
                      @compute @workgroup_size(1) fn main() { x[0] = x[1] * x[2] + x[3] - x[4]; }";
        event_loop_spirv(source, "main", &[], true).expect("builds")
    }

    /// The decorations of `words`: `(id, decoration)`.
    fn decorations(words: &[u32]) -> Vec<(u32, u32)> {
        let mut at = 5;
        let mut out = Vec::new();
        while at < words.len() {
            let (count, opcode) = ((words[at] >> 16) as usize, words[at] & 0xffff);
            if opcode == OP_DECORATE && count == 3 {
                out.push((words[at + 1], words[at + 2]));
            }
            at += count;
        }
        out
    }

    #[test]
    fn every_float_operation_is_marked_and_the_module_still_validates() {
        let words = module();
        let marked = decorations(&words)
            .iter()
            .filter(|d| d.1 == NO_CONTRACTION)
            .count();
        // the multiply, the add and the subtract
        assert_eq!(marked, 3, "{:?}", decorations(&words));
        // naga reads its own output back: the layout is still SPIR-V's
        let module = naga::front::spv::parse_u8_slice(
            bytemuck::cast_slice(&words),
            &naga::front::spv::Options::default(),
        );
        assert!(module.is_ok(), "{module:?}");
        // a second pass adds nothing
        let mut again = words.clone();
        assert_eq!(forbid_contraction(&mut again), Ok(0));
        assert_eq!(again, words);
    }

    #[test]
    fn bindings_are_numbered_as_wgpus_vulkan_layouts_number_them() {
        // bindings 0 and 5 used, 2 not: the layout's descriptors are 0 and 1, and the
        // unused binding gets a number of its own after them
        let source = "@group(0) @binding(0) var<storage, read> a: array<f32>;\n\
                      @group(0) @binding(2) var<storage, read> unused: array<f32>;\n\
                      @group(0) @binding(5) var<storage, read_write> b: array<f32>;\n\
                      @compute @workgroup_size(1) fn main() { b[0] = a[0]; }";
        let shader = exact_shader(source, "main", &[], true).expect("builds");
        let used: Vec<u32> = shader.bindings.iter().map(|b| b.binding).collect();
        assert_eq!(used, [0, 5]);
        // the SPIR-V's Binding decorations (decoration 33) are the layout's numbers
        let words = &shader.words;
        let mut at = 5;
        let mut numbers = Vec::new();
        while at < words.len() {
            let (count, opcode) = ((words[at] >> 16) as usize, words[at] & 0xffff);
            if opcode == OP_DECORATE && count == 4 && words[at + 2] == 33 {
                numbers.push(words[at + 3]);
            }
            at += count;
        }
        numbers.sort();
        assert!(numbers == [0, 1] || numbers == [0, 1, 2], "{numbers:?}");
        let module = naga::front::wgsl::parse_str(source).unwrap();
        let map = vulkan_bindings(&module, &shader.bindings);
        let at = |binding| map[&naga::ResourceBinding { group: 0, binding }].binding;
        assert_eq!((at(0), at(5), at(2)), (0, 1, 2));
    }

    #[test]
    fn what_is_not_spirv_is_refused_untouched() {
        let mut words = vec![1, 2, 3];
        assert!(forbid_contraction(&mut words).is_err());
        assert_eq!(words, [1, 2, 3]);
        // the last instruction (OpFunctionEnd, one word) said to be two words long
        let mut cut = module();
        let last = cut.len() - 1;
        cut[last] = instruction(2, cut[last] & 0xffff);
        let before = cut.clone();
        assert!(forbid_contraction(&mut cut).is_err());
        assert_eq!(cut, before);
    }
}
