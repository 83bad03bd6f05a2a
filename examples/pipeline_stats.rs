//! The GPU event loop as the device's own Vulkan driver compiles it: for each build of the
//! shader (ball-count bucket, threads a table, threads a row, tables a workgroup; f64), the
//! driver's statistics
//! of the compiled `simulate_tables` (`VK_KHR_pipeline_executable_properties`: registers,
//! spills, workgroup memory, instruction counts — whatever the driver reports). They say
//! what bounds how many tables a multiprocessor holds at once, which the timings alone
//! cannot tell (issue 26: the event-loop kernel waits ~100 µs an event whatever its
//! thread count).
//!
//! ```sh
//! cargo run --release --example pipeline_stats               # the default builds
//! cargo run --release --example pipeline_stats -- 16:64:64 64:64:1 16:16:64:4
//! ```
//!
//! Each argument is `BALLS:THREADS:ROW_THREADS[:TABLES]` (the bucket, a table's threads,
//! the most threads a missing row is split over, see `kisstime::gpu::ROW_THREADS`; the
//! tables a workgroup holds, 1 unless given, see `kisstime::gpu::TABLES_PER_GROUP`), with
//! `:unchecked` after it for the SPIR-V without wgpu's runtime checks (no index clamps, no
//! loop bounding: what `wgpu::Device::create_shader_module_trusted` with
//! `ShaderRuntimeChecks::unchecked()` compiles; kisstime does not run it), to see what the
//! checks cost in registers and instructions.
//! `benches/device.sh` runs it on a lent GPU. The SPIR-V is the module kisstime runs on
//! Vulkan (`kisstime::gpu::spirv::event_loop_spirv`: naga's, with indices and buffer
//! accesses clamped, loops bounded, workgroup memory zeroed by the shader, every float
//! operation `NoContraction`). Exit status 0 with a line saying
//! so where the device has no such statistics; 1 on any other failure.

use std::ffi::{CStr, c_char};

use ash::vk;
use kisstime::Precision;
use kisstime::gpu::shader::simulate_source;
use kisstime::gpu::spirv::event_loop_spirv;
use kisstime::gpu::{SimLayout, event_loop_constants};

/// The builds measured without arguments: the 16-ball bucket at each thread count, with
/// rows split and on one thread, several tables a workgroup, and without wgpu's runtime
/// checks; the larger buckets.
const DEFAULT_BUILDS: [&str; 10] = [
    "16:64:64",
    "16:64:1",
    "16:32:64",
    "16:16:64",
    "16:32:64:2",
    "16:16:64:2",
    "16:16:64:4",
    "16:64:64:unchecked",
    "32:64:64",
    "64:64:64",
];

fn main() {
    match run() {
        Ok(()) => {}
        Err(e) => {
            eprintln!("pipeline_stats: {e}");
            std::process::exit(1);
        }
    }
}

/// One build of the event loop: its bucket, a table's threads, row threads and tables a
/// workgroup.
#[derive(Clone, Copy)]
struct Build {
    balls: usize,
    threads: usize,
    row_threads: usize,
    tables: usize,
    /// Without wgpu's runtime checks (index clamps, loop bounding).
    unchecked: bool,
}

fn builds() -> Result<Vec<Build>, String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let specs: Vec<&str> = match args.is_empty() {
        true => DEFAULT_BUILDS.to_vec(),
        false => args.iter().map(String::as_str).collect(),
    };
    specs.into_iter().map(build).collect()
}

/// `BALLS:THREADS:ROW_THREADS[:TABLES][:unchecked]`.
fn build(spec: &str) -> Result<Build, String> {
    let (spec_nums, unchecked) = match spec.strip_suffix(":unchecked") {
        Some(rest) => (rest, true),
        None => (spec, false),
    };
    let expected = || {
        format!(
            "{spec:?}: expected BALLS (16, 32, 48 or 64):THREADS (16, 32 or 64):ROW_THREADS \
             (1 to 64), then :TABLES (1, 2, 4, 8 or 16) or nothing, then :unchecked or nothing"
        )
    };
    let parts: Vec<usize> = spec_nums
        .split(':')
        .map(|p| p.parse::<usize>())
        .collect::<Result<_, _>>()
        .map_err(|_| expected())?;
    let (balls, threads, row_threads, tables) = match parts[..] {
        [b, t, r] => (b, t, r, 1),
        [b, t, r, g] => (b, t, r, g),
        _ => return Err(expected()),
    };
    match (balls, threads, row_threads, tables) {
        (16 | 32 | 48 | 64, 16 | 32 | 64, 1..=64, 1 | 2 | 4 | 8 | 16) => Ok(Build {
            balls,
            threads,
            row_threads,
            tables,
            unchecked,
        }),
        _ => Err(expected()),
    }
}

/// The device chosen (the first that is not a CPU, else the first) and what it offers.
struct Chosen {
    physical: vk::PhysicalDevice,
    name: String,
    queue_family: u32,
    robust2: bool,
    zero_init: bool,
    /// Whether it has `VK_KHR_pipeline_executable_properties`.
    stats: bool,
}

fn run() -> Result<(), String> {
    let builds = builds()?;
    // SAFETY: loading the system's Vulkan loader (libvulkan) and calling it as its
    // specification says; every handle made here is destroyed before returning.
    let entry = unsafe { ash::Entry::load() }.map_err(|e| format!("no Vulkan loader: {e}"))?;
    let app = vk::ApplicationInfo::default()
        .application_name(c"kisstime pipeline_stats")
        .api_version(vk::API_VERSION_1_2);
    let instance = unsafe {
        entry.create_instance(
            &vk::InstanceCreateInfo::default().application_info(&app),
            None,
        )
    }
    .map_err(|e| format!("no Vulkan instance: {e}"))?;
    let result = with_instance(&instance, &builds);
    unsafe { instance.destroy_instance(None) };
    result
}

fn with_instance(instance: &ash::Instance, builds: &[Build]) -> Result<(), String> {
    let chosen = choose(instance)?;
    println!("device: {}", chosen.name);
    let float64 = unsafe { instance.get_physical_device_features(chosen.physical) }.shader_float64;
    if float64 != vk::TRUE {
        println!("pipeline statistics: {} has no f64 in shaders", chosen.name);
        return Ok(());
    }
    // without the extension each pipeline is still built (the driver compiles it), with no
    // statistics to report
    let stats = chosen.stats;
    if !stats {
        println!(
            "pipeline statistics: {} has no VK_KHR_pipeline_executable_properties: \
             the pipelines are built, with no statistics",
            chosen.name
        );
    }
    let mut extensions: Vec<*const c_char> = Vec::new();
    let mut exec = vk::PhysicalDevicePipelineExecutablePropertiesFeaturesKHR::default()
        .pipeline_executable_info(true);
    let mut robust =
        vk::PhysicalDeviceRobustness2FeaturesEXT::default().robust_buffer_access2(true);
    let mut zero = vk::PhysicalDeviceZeroInitializeWorkgroupMemoryFeatures::default()
        .shader_zero_initialize_workgroup_memory(true);
    let features = vk::PhysicalDeviceFeatures::default()
        .shader_float64(true)
        .robust_buffer_access(chosen.robust2);
    let priorities = [1.0f32];
    let queues = [vk::DeviceQueueCreateInfo::default()
        .queue_family_index(chosen.queue_family)
        .queue_priorities(&priorities)];
    let mut info = vk::DeviceCreateInfo::default()
        .queue_create_infos(&queues)
        .enabled_features(&features);
    if stats {
        extensions.push(ash::khr::pipeline_executable_properties::NAME.as_ptr());
        info = info.push_next(&mut exec);
    }
    if chosen.robust2 {
        extensions.push(ash::ext::robustness2::NAME.as_ptr());
        info = info.push_next(&mut robust);
    }
    if chosen.zero_init {
        info = info.push_next(&mut zero);
    }
    let info = info.enabled_extension_names(&extensions);
    let device = unsafe { instance.create_device(chosen.physical, &info, None) }
        .map_err(|e| format!("{}: no device: {e}", chosen.name))?;
    let result = builds
        .iter()
        .try_for_each(|b| report(instance, &device, &chosen, *b));
    unsafe { device.destroy_device(None) };
    result
}

fn choose(instance: &ash::Instance) -> Result<Chosen, String> {
    let devices =
        unsafe { instance.enumerate_physical_devices() }.map_err(|e| format!("no devices: {e}"))?;
    let props = |d: vk::PhysicalDevice| unsafe { instance.get_physical_device_properties(d) };
    let physical = devices
        .iter()
        .copied()
        .find(|&d| props(d).device_type != vk::PhysicalDeviceType::CPU)
        .or_else(|| devices.first().copied())
        .ok_or("no Vulkan device")?;
    let p = props(physical);
    let name = p
        .device_name_as_c_str()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let families = unsafe { instance.get_physical_device_queue_family_properties(physical) };
    let queue_family = families
        .iter()
        .position(|f| f.queue_flags.contains(vk::QueueFlags::COMPUTE))
        .ok_or_else(|| format!("{name}: no compute queue"))? as u32;
    let exts = unsafe { instance.enumerate_device_extension_properties(physical) }
        .map_err(|e| e.to_string())?;
    let has = |n: &CStr| {
        exts.iter()
            .any(|x| x.extension_name_as_c_str().is_ok_and(|e| e == n))
    };
    let mut robust = vk::PhysicalDeviceRobustness2FeaturesEXT::default();
    let mut zero = vk::PhysicalDeviceZeroInitializeWorkgroupMemoryFeatures::default();
    let mut features = vk::PhysicalDeviceFeatures2::default();
    let has_robust2 = has(ash::ext::robustness2::NAME);
    let has_zero = p.api_version >= vk::API_VERSION_1_3
        || has(ash::khr::zero_initialize_workgroup_memory::NAME);
    if has_robust2 {
        features = features.push_next(&mut robust);
    }
    if has_zero {
        features = features.push_next(&mut zero);
    }
    unsafe { instance.get_physical_device_features2(physical, &mut features) };
    let robust2 = has_robust2 && robust.robust_buffer_access2 == vk::TRUE;
    let zero_init = has_zero && zero.shader_zero_initialize_workgroup_memory == vk::TRUE;
    Ok(Chosen {
        physical,
        name,
        queue_family,
        robust2,
        zero_init,
        stats: has(ash::khr::pipeline_executable_properties::NAME),
    })
}

/// The SPIR-V kisstime runs for build `b` (`kisstime::gpu::spirv`: naga's, every float
/// operation `NoContraction`), and its workgroup's threads.
fn spirv(b: Build) -> Result<(Vec<u32>, usize), String> {
    let layout = SimLayout::for_balls(b.balls);
    let constants = event_loop_constants(&layout, b.threads, b.row_threads, b.tables);
    let source = simulate_source(Precision::F64, b.balls, b.tables);
    let threads = constants
        .iter()
        .find(|(name, _)| *name == "LOOP_THREADS")
        .map_or(b.threads, |&(_, v)| v as usize);
    let words = event_loop_spirv(&source, "simulate_tables", &constants, !b.unchecked)?;
    Ok((words, threads))
}

/// Builds one pipeline with its statistics captured and prints them.
fn report(
    instance: &ash::Instance,
    device: &ash::Device,
    chosen: &Chosen,
    b: Build,
) -> Result<(), String> {
    let stats = chosen.stats;
    let (code, threads) = spirv(b)?;
    let label = format!(
        "event loop f64, {} balls, {threads} threads a table, a row over at most {}, {} a workgroup{}",
        b.balls,
        b.row_threads,
        match b.tables {
            1 => "one table".to_owned(),
            n => format!("{n} tables"),
        },
        if b.unchecked {
            ", without wgpu's runtime checks"
        } else {
            ""
        }
    );
    // the bindings of event_loop.wgsl: a uniform, then storage buffers
    let bindings: Vec<vk::DescriptorSetLayoutBinding> = (0..9)
        .map(|k| {
            vk::DescriptorSetLayoutBinding::default()
                .binding(k)
                .descriptor_type(if k == 0 {
                    vk::DescriptorType::UNIFORM_BUFFER
                } else {
                    vk::DescriptorType::STORAGE_BUFFER
                })
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::COMPUTE)
        })
        .collect();
    let exec = ash::khr::pipeline_executable_properties::Device::new(instance, device);
    unsafe {
        let set = device
            .create_descriptor_set_layout(
                &vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings),
                None,
            )
            .map_err(|e| e.to_string())?;
        let sets = [set];
        let layout = device
            .create_pipeline_layout(
                &vk::PipelineLayoutCreateInfo::default().set_layouts(&sets),
                None,
            )
            .map_err(|e| e.to_string());
        let Ok(layout) = layout else {
            device.destroy_descriptor_set_layout(set, None);
            return Err(format!("{label}: {}", layout.unwrap_err()));
        };
        let module = device
            .create_shader_module(&vk::ShaderModuleCreateInfo::default().code(&code), None)
            .map_err(|e| format!("{label}: {e}"));
        let result = module.and_then(|module| {
            let stage = vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::COMPUTE)
                .module(module)
                .name(c"simulate_tables");
            let flags = match stats {
                true => vk::PipelineCreateFlags::CAPTURE_STATISTICS_KHR,
                false => vk::PipelineCreateFlags::empty(),
            };
            let info = vk::ComputePipelineCreateInfo::default()
                .flags(flags)
                .stage(stage)
                .layout(layout);
            let made = device
                .create_compute_pipelines(vk::PipelineCache::null(), &[info], None)
                .map_err(|(_, e)| format!("{label}: the driver does not build it: {e}"));
            let printed = made.and_then(|pipelines| {
                let pipeline = pipelines[0];
                let printed = match stats {
                    true => print_statistics(&exec, pipeline, &label),
                    false => {
                        println!(
                            "{label}: built ({} SPIR-V words), no statistics",
                            code.len()
                        );
                        Ok(())
                    }
                };
                device.destroy_pipeline(pipeline, None);
                printed
            });
            device.destroy_shader_module(module, None);
            printed
        });
        device.destroy_pipeline_layout(layout, None);
        device.destroy_descriptor_set_layout(set, None);
        result
    }
}

/// # Safety
/// `pipeline` was made on `exec`'s device with `CAPTURE_STATISTICS_KHR`.
unsafe fn print_statistics(
    exec: &ash::khr::pipeline_executable_properties::Device,
    pipeline: vk::Pipeline,
    label: &str,
) -> Result<(), String> {
    let info = vk::PipelineInfoKHR::default().pipeline(pipeline);
    let executables = unsafe { exec.get_pipeline_executable_properties(&info) }
        .map_err(|e| format!("{label}: no executables: {e}"))?;
    for (k, x) in executables.iter().enumerate() {
        let name = x
            .name_as_c_str()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let stats = unsafe {
            exec.get_pipeline_executable_statistics(
                &vk::PipelineExecutableInfoKHR::default()
                    .pipeline(pipeline)
                    .executable_index(k as u32),
            )
        }
        .map_err(|e| format!("{label}: no statistics: {e}"))?;
        let values: Vec<String> = stats
            .iter()
            .map(|s| {
                let name = s
                    .name_as_c_str()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_default();
                // SAFETY: the union's member is the one `format` names
                let value = unsafe {
                    match s.format {
                        vk::PipelineExecutableStatisticFormatKHR::BOOL32 => {
                            (s.value.b32 == vk::TRUE).to_string()
                        }
                        vk::PipelineExecutableStatisticFormatKHR::INT64 => s.value.i64.to_string(),
                        vk::PipelineExecutableStatisticFormatKHR::UINT64 => s.value.u64.to_string(),
                        vk::PipelineExecutableStatisticFormatKHR::FLOAT64 => {
                            s.value.f64.to_string()
                        }
                        _ => "?".into(),
                    }
                };
                format!("{name} {value}")
            })
            .collect();
        println!(
            "{label}: {name} (subgroup {}): {}",
            x.subgroup_size,
            if values.is_empty() {
                "no statistics".into()
            } else {
                values.join(", ")
            }
        );
    }
    if executables.is_empty() {
        println!("{label}: the driver reports no executable");
    }
    Ok(())
}
