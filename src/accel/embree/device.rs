//! The Embree device: creation, the version check, and the error callback.

use std::ffi::{CStr, CString, c_char, c_void};
use std::ptr::NonNull;
use std::sync::atomic::{AtomicI64, Ordering};
use std::sync::{Arc, Mutex};

use super::owned::UserPtr;
use super::sys;
use crate::error::{Error, Result};

/// What the device callbacks record: errors, drained after every build, commit
/// and batch, and the bytes Embree has allocated. Embree may call either
/// callback from any thread.
#[derive(Default)]
struct Monitor {
    errors: Mutex<Vec<String>>,
    bytes: AtomicI64,
}

impl Monitor {
    fn push(&self, message: String) {
        self.errors
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push(message);
    }

    fn drain(&self) -> Vec<String> {
        std::mem::take(&mut *self.errors.lock().unwrap_or_else(|e| e.into_inner()))
    }
}

struct DeviceHandle {
    raw: NonNull<sys::RTCDeviceTy>,
    // The callbacks' user pointer. Declared after `raw`: the device is released
    // before the monitor is freed.
    monitor: UserPtr<Monitor>,
}

impl Drop for DeviceHandle {
    fn drop(&mut self) {
        // SAFETY: `raw` came from rtcNewDevice and is released exactly once, here; every
        // scene holds an `Arc` of this handle, so none outlives it.
        unsafe { sys::rtcReleaseDevice(self.raw.as_ptr()) };
    }
}

// SAFETY: Embree's API documentation states that device-level calls (creating objects,
// setting callbacks, querying properties) are thread-safe, and the monitor, owned through
// `UserPtr` like a Box, is a Mutex and an atomic.
unsafe impl Send for DeviceHandle {}
// SAFETY: as for Send: sharing `&DeviceHandle` only allows thread-safe device calls.
unsafe impl Sync for DeviceHandle {}

/// A shared Embree device. Cloning is cheap (an `Arc`).
#[derive(Clone)]
pub struct Device(Arc<DeviceHandle>);

/// The version of an Embree library or header, as `major * 10000 + minor * 100 + patch`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Version(pub u32);

impl Version {
    pub fn major(self) -> u32 {
        self.0 / 10000
    }
}

impl std::fmt::Display for Version {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}.{}.{}",
            self.0 / 10000,
            self.0 / 100 % 100,
            self.0 % 100
        )
    }
}

/// The version of the header the bindings were generated from.
pub const HEADER_VERSION: Version = Version(sys::RTC_VERSION);

extern "C" fn error_callback(user_ptr: *mut c_void, code: sys::RTCError, message: *const c_char) {
    // No panic may unwind into Embree; there is nowhere to report one from here,
    // so a failure to record the message is dropped.
    let _ = std::panic::catch_unwind(|| {
        let text = if message.is_null() {
            String::from("(no message)")
        } else {
            // SAFETY: Embree passes a NUL-terminated string valid for this call; it is
            // copied before returning.
            unsafe { CStr::from_ptr(message) }
                .to_string_lossy()
                .into_owned()
        };
        // SAFETY: `user_ptr` is the `Monitor` registered in `Device::with_config`, owned by
        // the DeviceHandle, which releases the device before freeing it.
        let monitor = unsafe { &*(user_ptr as *const Monitor) };
        monitor.push(format!("{} (code {code})", text.trim_end()));
    });
}

extern "C" fn memory_callback(user_ptr: *mut c_void, bytes: isize, _post: bool) -> bool {
    // SAFETY: as in `error_callback`. An atomic add cannot panic.
    let monitor = unsafe { &*(user_ptr as *const Monitor) };
    monitor.bytes.fetch_add(bytes as i64, Ordering::Relaxed);
    // Never refuse an allocation.
    true
}

impl Device {
    /// Creates a device with Embree's default configuration.
    pub fn new() -> Result<Device> {
        Device::with_config("")
    }

    /// Creates a device with an Embree configuration string such as `"threads=1,verbose=1"`,
    /// and refuses a library of another major version than the header, or an older one.
    pub fn with_config(config: &str) -> Result<Device> {
        let config = CString::new(config)
            .map_err(|_| Error::Input("Embree configuration contains a NUL byte".into()))?;
        // SAFETY: `config` is NUL-terminated and lives across the call.
        let raw = unsafe { sys::rtcNewDevice(config.as_ptr()) };
        let Some(raw) = NonNull::new(raw) else {
            // SAFETY: a null device asks for the thread's creation error.
            let code = unsafe { sys::rtcGetDeviceError(std::ptr::null_mut()) };
            return Err(Error::Embree(format!(
                "cannot create a device (error code {code}, configuration {config:?})"
            )));
        };
        let handle = DeviceHandle {
            raw,
            monitor: UserPtr::new(Box::default()),
        };
        let monitor = handle.monitor.as_c_void();
        // SAFETY: the device is valid; the monitor is owned by `handle` and outlives the
        // device (field order and Drop above); the callback only reads it through `&Monitor`.
        unsafe { sys::rtcSetDeviceErrorFunction(raw.as_ptr(), Some(error_callback), monitor) };
        // SAFETY: as for the error function.
        unsafe {
            sys::rtcSetDeviceMemoryMonitorFunction(raw.as_ptr(), Some(memory_callback), monitor)
        };
        let device = Device(Arc::new(handle));
        let library = device.library_version();
        if library.major() != HEADER_VERSION.major() || library < HEADER_VERSION {
            return Err(Error::Embree(format!(
                "the Embree library is version {library} but sturmray was built against the \
                 {HEADER_VERSION} header; rebuild against this library's header, or install \
                 a library of the same major version, no older than the header"
            )));
        }
        device.check()?;
        Ok(device)
    }

    /// The version the loaded library reports, which may differ from the header's.
    pub fn library_version(&self) -> Version {
        // SAFETY: the device handle is valid; the property is a plain integer query.
        let v = unsafe {
            sys::rtcGetDeviceProperty(
                self.raw(),
                sys::RTCDeviceProperty_RTC_DEVICE_PROPERTY_VERSION,
            )
        };
        Version(u32::try_from(v).unwrap_or(0))
    }

    /// Bytes Embree currently holds for this device's scenes, from its memory monitor.
    pub fn bytes_in_use(&self) -> i64 {
        self.0.monitor.get().bytes.load(Ordering::Relaxed)
    }

    pub(super) fn raw(&self) -> *mut sys::RTCDeviceTy {
        self.0.raw.as_ptr()
    }

    /// Turns every error Embree reported since the last check into an `Error`.
    pub(super) fn check(&self) -> Result<()> {
        let errors = self.0.monitor.get().drain();
        if errors.is_empty() {
            Ok(())
        } else {
            Err(Error::Embree(errors.join("; ")))
        }
    }
}
