//! The Vulkan context: a headless instance (no surface), one device with one compute queue
//! and the memory allocator, plus the optional validation layer whose messages are recorded
//! so that tests can assert there were none.
//!
//! Teardown order (Drop): allocator, device, debug messenger, instance. Every resource made
//! from a context (buffers, kernels, command buffers, query pools) holds an `Arc<Context>`
//! and frees itself on drop, so the context always goes last.
//!
//! # Threads
//!
//! `Context` is `Send + Sync` (an `Arc<Context>` is shared by backends and the renderer),
//! and that is sound because everything Vulkan requires to be externally synchronised is
//! either locked here or not shared:
//!
//! - the queue (`vkQueueSubmit`, `vkQueueWaitIdle`, `vkDeviceWaitIdle`) is only reachable
//!   through [`Context::submit`] and [`Context::wait_idle`], which hold a mutex;
//! - the allocator sits behind a mutex ([`Context::allocator`]);
//! - there is no shared command pool: each command buffer
//!   ([`crate::gpu::commands::Recorded`]) owns its pool, so allocating, recording and
//!   freeing it synchronise with nothing but its owner.
//!
//! The compile-time assertion below keeps `Sync` a checked fact rather than an accident.
//!
//! # One loader, one context per device
//!
//! The Vulkan loader is loaded once per process and never unloaded, and so is each of the
//! two instances (without and with the validation layer): NVIDIA's driver (580, H200)
//! refuses `vkCreateInstance` with `VK_ERROR_INCOMPATIBLE_DRIVER` after a few dozen instances
//! were created and destroyed in one process, even with the loader kept loaded
//! (`tests/gpu_lifecycle.rs` on an H200, 2026-11-26). An instance is bounded process state,
//! not a leak: devices, messengers, allocations, pools and pipelines are freed with their
//! context. [`Context::shared`] hands every caller asking for the same device and validation
//! the one live context (instance, device, queue, allocator), created under a lock, so
//! backends made from many threads at once never create instances concurrently (the
//! validation layer crashed doing that); the context is freed with the last backend
//! holding it. [`live_contexts`] counts the contexts alive in the process: since every
//! resource holds an `Arc<Context>`, a leaked buffer, kernel or pool keeps it above zero.

use std::ffi::{c_void, CStr};
use std::mem::ManuallyDrop;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, OnceLock, Weak};

use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};

use super::device::{self, DeviceInfo, DeviceSelector};
use crate::error::{Error, Result, VkContext};

/// Name of the Khronos validation layer.
pub const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// How to create a [`Context`].
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ContextOptions {
    /// Which device to use.
    pub device: DeviceSelector,
    /// Enable `VK_LAYER_KHRONOS_validation` and record its warnings and errors.
    pub validation: bool,
}

/// Messages of the validation layer (severity warning or error), in arrival order.
#[derive(Debug, Default)]
pub struct MessageLog {
    messages: Mutex<Vec<String>>,
}

/// What the validation layer said while the validated instance was created (the context's
/// own messenger exists only afterwards); every validated context reports it too.
static INSTANCE_LOG: MessageLog = MessageLog::new();

impl MessageLog {
    /// An empty log.
    pub const fn new() -> Self {
        MessageLog {
            messages: Mutex::new(Vec::new()),
        }
    }

    /// A copy of every message so far.
    pub fn messages(&self) -> Vec<String> {
        self.messages
            .lock()
            .map(|m| m.clone())
            .unwrap_or_else(|p| p.into_inner().clone())
    }

    fn push(&self, text: String) {
        match self.messages.lock() {
            Ok(mut m) => m.push(text),
            Err(p) => p.into_inner().push(text),
        }
    }
}

unsafe extern "system" fn on_debug_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    // SAFETY: `user` is the `MessageLog` that the context keeps alive (in an Arc) until the
    // messenger is destroyed; `data` is valid for the duration of the callback.
    unsafe {
        if let (Some(log), Some(data)) = ((user as *const MessageLog).as_ref(), data.as_ref()) {
            let text = data
                .message_as_c_str()
                .map(|c| c.to_string_lossy().into_owned())
                .unwrap_or_default();
            log.push(format!("[{severity:?} {types:?}] {text}"));
        }
    }
    vk::FALSE
}

struct Debug {
    loader: ash::ext::debug_utils::Instance,
    messenger: vk::DebugUtilsMessengerEXT,
}

/// Instance, device, queue and allocator; see the module doc for teardown and threads.
pub struct Context {
    info: DeviceInfo,
    device: ash::Device,
    /// Locked for every use: queue operations need external synchronisation.
    queue: Mutex<vk::Queue>,
    allocator: ManuallyDrop<Mutex<Allocator>>,
    names: Option<ash::ext::debug_utils::Device>,
    debug: Option<Debug>,
    log: Arc<MessageLog>,
}

/// Contexts alive in this process.
static LIVE_CONTEXTS: AtomicUsize = AtomicUsize::new(0);

/// The live context of each option set that [`Context::shared`] handed out.
static SHARED: Mutex<Vec<(ContextOptions, Weak<Context>)>> = Mutex::new(Vec::new());

/// Held while an instance or device is created or destroyed: one at a time per process.
static LIFECYCLE: Mutex<()> = Mutex::new(());

/// The number of [`Context`]s alive in this process (every Vulkan object the engine makes
/// keeps its context alive, so this is zero once everything is freed).
pub fn live_contexts() -> usize {
    LIVE_CONTEXTS.load(Ordering::SeqCst)
}

// `Context` is shared between threads by design (see the module doc); this fails to
// compile if a field ever makes it `!Send` or `!Sync`.
const _: fn() = || {
    fn assert_send_sync<T: Send + Sync>() {}
    assert_send_sync::<Context>();
};

/// The Vulkan loader, loaded on first use and kept for the life of the process.
fn load_entry() -> Result<&'static ash::Entry> {
    static ENTRY: OnceLock<ash::Entry> = OnceLock::new();
    if let Some(entry) = ENTRY.get() {
        return Ok(entry);
    }
    // SAFETY: loading the system Vulkan loader, whose initialisation has no preconditions;
    // a second thread racing here loads it twice and drops its copy (a reference count).
    let entry = unsafe { ash::Entry::load() }.map_err(|e| {
        Error::Gpu(format!(
            "cannot load the Vulkan loader (libvulkan.so.1): {e}"
        ))
    })?;
    Ok(ENTRY.get_or_init(|| entry))
}

/// The process's instance without or with the validation layer, and whether it has
/// `VK_EXT_debug_utils`; created on first use (the caller holds [`LIFECYCLE`]), never
/// destroyed (module doc).
fn shared_instance(entry: &ash::Entry, validation: bool) -> Result<(ash::Instance, bool)> {
    static INSTANCES: Mutex<[Option<(ash::Instance, bool)>; 2]> = Mutex::new([None, None]);
    let mut instances = INSTANCES.lock().unwrap_or_else(|p| p.into_inner());
    let slot = &mut instances[usize::from(validation)];
    if let Some(made) = slot {
        return Ok(made.clone());
    }
    let made = create_instance(entry, validation, &INSTANCE_LOG)?;
    *slot = Some(made.clone());
    Ok(made)
}

fn create_instance(
    entry: &ash::Entry,
    validation: bool,
    log: &'static MessageLog,
) -> Result<(ash::Instance, bool)> {
    // SAFETY: plain queries and instance creation with create infos that outlive the calls.
    unsafe {
        let extensions = entry
            .enumerate_instance_extension_properties(None)
            .vk("vkEnumerateInstanceExtensionProperties")?;
        let has_debug_utils = extensions
            .iter()
            .any(|e| e.extension_name_as_c_str() == Ok(ash::ext::debug_utils::NAME));
        let mut layers = Vec::new();
        if validation {
            let available = entry
                .enumerate_instance_layer_properties()
                .vk("vkEnumerateInstanceLayerProperties")?;
            if !available
                .iter()
                .any(|l| l.layer_name_as_c_str() == Ok(VALIDATION_LAYER))
            {
                return Err(Error::Gpu(
                    "validation requested but VK_LAYER_KHRONOS_validation is not installed (Debian: vulkan-validationlayers)".into(),
                ));
            }
            if !has_debug_utils {
                return Err(Error::Gpu(
                    "validation requested but VK_EXT_debug_utils is missing".into(),
                ));
            }
            layers.push(VALIDATION_LAYER.as_ptr());
        }
        let ext_names: Vec<*const i8> = if has_debug_utils {
            vec![ash::ext::debug_utils::NAME.as_ptr()]
        } else {
            Vec::new()
        };
        let app = vk::ApplicationInfo::default()
            .application_name(c"tetrasim")
            .engine_name(c"tetrasim")
            .api_version(device::REQUIRED_API);
        let mut messenger_info = messenger_create_info(log);
        let mut info = vk::InstanceCreateInfo::default()
            .application_info(&app)
            .enabled_layer_names(&layers)
            .enabled_extension_names(&ext_names);
        if validation {
            info = info.push_next(&mut messenger_info);
        }
        let instance = entry.create_instance(&info, None).vk("vkCreateInstance")?;
        Ok((instance, has_debug_utils))
    }
}

fn messenger_create_info(log: &MessageLog) -> vk::DebugUtilsMessengerCreateInfoEXT<'static> {
    vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(
            vk::DebugUtilsMessageSeverityFlagsEXT::WARNING
                | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR,
        )
        .message_type(
            vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
        )
        .pfn_user_callback(Some(on_debug_message))
        .user_data(log as *const MessageLog as *mut c_void)
}

fn enumerate(instance: &ash::Instance) -> Result<(Vec<vk::PhysicalDevice>, Vec<DeviceInfo>)> {
    // SAFETY: the instance is alive.
    let handles =
        unsafe { instance.enumerate_physical_devices() }.vk("vkEnumeratePhysicalDevices")?;
    let infos = handles
        .iter()
        .enumerate()
        .map(|(i, &pd)| DeviceInfo::query(instance, pd, i))
        .collect::<Result<_>>()?;
    Ok((handles, infos))
}

/// Lists every Vulkan device with its limits and features (for `tetrasim info`).
pub fn list_devices() -> Result<Vec<DeviceInfo>> {
    let _one_at_a_time = LIFECYCLE.lock().unwrap_or_else(|p| p.into_inner());
    let entry = load_entry()?;
    let (instance, _) = shared_instance(entry, false)?;
    enumerate(&instance).map(|(_, infos)| infos)
}

impl Context {
    /// The process's live context for `options`, created if there is none (see the module
    /// doc). Callers that need a context of their own (e.g. to count its validation
    /// messages alone) use [`Context::new`].
    pub fn shared(options: &ContextOptions) -> Result<Arc<Self>> {
        let mut shared = SHARED.lock().unwrap_or_else(|p| p.into_inner());
        shared.retain(|(_, ctx)| ctx.strong_count() > 0);
        if let Some(ctx) = shared
            .iter()
            .find(|(o, _)| o == options)
            .and_then(|(_, ctx)| ctx.upgrade())
        {
            return Ok(ctx);
        }
        let ctx = Arc::new(Context::new(options)?);
        shared.push((options.clone(), Arc::downgrade(&ctx)));
        Ok(ctx)
    }

    /// Creates the instance and the selected device, with float atomics enabled where the
    /// device has them.
    pub fn new(options: &ContextOptions) -> Result<Self> {
        let _one_at_a_time = LIFECYCLE.lock().unwrap_or_else(|p| p.into_inner());
        let entry = load_entry()?;
        let log = Arc::new(MessageLog::default());
        let (instance, has_debug_utils) = shared_instance(entry, options.validation)?;
        let mut ctx = PartialContext {
            debug: None,
            armed: true,
        };
        if options.validation {
            let loader = ash::ext::debug_utils::Instance::new(entry, &instance);
            // SAFETY: the create info's user data (the log) outlives the messenger.
            let messenger =
                unsafe { loader.create_debug_utils_messenger(&messenger_create_info(&log), None) }
                    .vk("vkCreateDebugUtilsMessengerEXT")?;
            ctx.debug = Some(Debug { loader, messenger });
        }
        let (handles, infos) = enumerate(&instance)?;
        let chosen = device::select(&infos, &options.device)?;
        let info = infos[chosen].clone();
        let pd = handles[chosen];
        let family = info
            .compute_family
            .ok_or_else(|| Error::Gpu(format!("device `{}` has no compute queue", info.name)))?;

        let priorities = [1.0f32];
        let queues = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(family)
            .queue_priorities(&priorities)];
        let mut extensions = Vec::new();
        let mut atomic = vk::PhysicalDeviceShaderAtomicFloatFeaturesEXT::default()
            .shader_buffer_float32_atomic_add(true);
        let mut create = vk::DeviceCreateInfo::default().queue_create_infos(&queues);
        if info.float_atomic_add {
            extensions.push(ash::ext::shader_atomic_float::NAME.as_ptr());
            create = create.push_next(&mut atomic);
        }
        create = create.enabled_extension_names(&extensions);
        // SAFETY: `pd` belongs to `instance`; the create info and its chain outlive the call.
        let device = unsafe { instance.create_device(pd, &create, None) }.vk("vkCreateDevice")?;
        // SAFETY: the family and index were requested above.
        let queue = unsafe { device.get_device_queue(family, 0) };
        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: instance.clone(),
            device: device.clone(),
            physical_device: pd,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        });
        let allocator = match allocator {
            Ok(a) => a,
            Err(e) => {
                // SAFETY: nothing was made from the device.
                unsafe { device.destroy_device(None) };
                return Err(Error::Gpu(format!("creating the memory allocator: {e}")));
            }
        };
        let names = has_debug_utils.then(|| ash::ext::debug_utils::Device::new(&instance, &device));
        let debug = ctx.disarm();
        LIVE_CONTEXTS.fetch_add(1, Ordering::SeqCst);
        Ok(Context {
            info,
            device,
            queue: Mutex::new(queue),
            allocator: ManuallyDrop::new(Mutex::new(allocator)),
            names,
            debug,
            log,
        })
    }

    /// The chosen device's properties.
    pub fn info(&self) -> &DeviceInfo {
        &self.info
    }

    /// The logical device.
    pub fn device(&self) -> &ash::Device {
        &self.device
    }

    /// The compute queue's family (command pools are made for it).
    pub fn queue_family(&self) -> Result<u32> {
        self.info
            .compute_family
            .ok_or_else(|| Error::Gpu(format!("device `{}` has no compute queue", self.info.name)))
    }

    /// `vkQueueSubmit` of `submits` to the compute queue, signalling `fence`, under the
    /// queue's lock.
    ///
    /// # Safety
    ///
    /// As for `vkQueueSubmit`: every command buffer is executable and not pending (or made
    /// for simultaneous use), `fence` is unsignalled and not pending, and every handle
    /// belongs to this device and stays alive until the fence signals.
    pub unsafe fn submit(&self, submits: &[vk::SubmitInfo<'_>], fence: vk::Fence) -> Result<()> {
        let queue = self.lock_queue()?;
        // SAFETY: the queue is locked (external synchronisation); the rest is the caller's
        // contract above.
        unsafe { self.device.queue_submit(*queue, submits, fence) }.vk("vkQueueSubmit")
    }

    /// `vkDeviceWaitIdle` under the queue's lock (it synchronises with the queue).
    pub fn wait_idle(&self) -> Result<()> {
        let _queue = self.lock_queue()?;
        // SAFETY: the only queue is locked, as vkDeviceWaitIdle requires.
        unsafe { self.device.device_wait_idle() }.vk("vkDeviceWaitIdle")
    }

    fn lock_queue(&self) -> Result<MutexGuard<'_, vk::Queue>> {
        self.queue
            .lock()
            .map_err(|_| Error::Gpu("the queue mutex is poisoned (an earlier panic)".into()))
    }

    /// The memory allocator.
    pub fn allocator(&self) -> Result<MutexGuard<'_, Allocator>> {
        self.allocator
            .lock()
            .map_err(|_| Error::Gpu("the allocator mutex is poisoned (an earlier panic)".into()))
    }

    /// Gives a Vulkan object a debug name (shown by the validation layer and GPU tools);
    /// does nothing without `VK_EXT_debug_utils`.
    pub fn set_name<H: vk::Handle>(&self, handle: H, name: &str) {
        let Some(names) = &self.names else { return };
        let Ok(name) = std::ffi::CString::new(name) else {
            return;
        };
        let info = vk::DebugUtilsObjectNameInfoEXT::default()
            .object_handle(handle)
            .object_name(&name);
        // SAFETY: the handle belongs to this device; naming failure is harmless, so ignored.
        let _ = unsafe { names.set_debug_utils_object_name(&info) };
    }

    /// Opens a labelled region in `cmd` (RenderDoc, Nsight and the validation layer show the
    /// commands inside under `label`); close it with [`Context::end_label`]. Does nothing
    /// without `VK_EXT_debug_utils`.
    pub fn begin_label(&self, cmd: vk::CommandBuffer, label: &str) {
        let Some(names) = &self.names else { return };
        let Ok(label) = std::ffi::CString::new(label) else {
            return;
        };
        let info = vk::DebugUtilsLabelEXT::default().label_name(&label);
        // SAFETY: `cmd` is a command buffer of this device in the recording state.
        unsafe { names.cmd_begin_debug_utils_label(cmd, &info) };
    }

    /// Closes the region opened by the last [`Context::begin_label`] on `cmd`.
    pub fn end_label(&self, cmd: vk::CommandBuffer) {
        let Some(names) = &self.names else { return };
        // SAFETY: `cmd` is recording and has an open label region (begun by `begin_label`,
        // which does nothing exactly when this does nothing).
        unsafe { names.cmd_end_debug_utils_label(cmd) };
    }

    /// Whether the validation layer is on.
    pub fn validation(&self) -> bool {
        self.debug.is_some()
    }

    /// Every validation warning and error recorded so far.
    pub fn validation_messages(&self) -> Vec<String> {
        let mut messages = match self.debug.is_some() {
            true => INSTANCE_LOG.messages(),
            false => Vec::new(),
        };
        messages.extend(self.log.messages());
        messages
    }
}

impl Drop for Context {
    fn drop(&mut self) {
        let _one_at_a_time = LIFECYCLE.lock().unwrap_or_else(|p| p.into_inner());
        // SAFETY: every resource made from the context holds an Arc to it, so all are gone
        // (see the module doc); the order below is children before parents.
        unsafe {
            let _ = self.device.device_wait_idle();
            ManuallyDrop::drop(&mut self.allocator);
            self.device.destroy_device(None);
            if let Some(debug) = self.debug.take() {
                debug
                    .loader
                    .destroy_debug_utils_messenger(debug.messenger, None);
            }
        }
        LIVE_CONTEXTS.fetch_sub(1, Ordering::SeqCst);
    }
}

/// Destroys the messenger if context creation fails half-way (the instance stays: module
/// doc).
struct PartialContext {
    debug: Option<Debug>,
    armed: bool,
}

impl PartialContext {
    /// Hands the messenger over to its final owner.
    fn disarm(&mut self) -> Option<Debug> {
        self.armed = false;
        self.debug.take()
    }
}

impl Drop for PartialContext {
    fn drop(&mut self) {
        if !self.armed {
            return;
        }
        if let Some(debug) = self.debug.take() {
            // SAFETY: only reached on an error path, before any device was kept; the
            // caller holds LIFECYCLE, which serialises use of the shared instance.
            unsafe {
                debug
                    .loader
                    .destroy_debug_utils_messenger(debug.messenger, None)
            };
        }
    }
}
