//! Status codes, the last error's message per thread, and the guard every entry point runs
//! its body in: errors become a status and a message, panics never unwind into the host.

use std::cell::RefCell;
use std::ffi::{c_char, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};

use ellipsoid_splat::Error;

/// What a call did.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EsStatus {
    /// It succeeded.
    Success = 0,
    /// An argument was null, out of range or inconsistent (the message names which).
    ErrorInvalidArgument = 1,
    /// The device lacks a feature or format the call needs, or the host did not enable it.
    ErrorUnsupported = 2,
    /// A Vulkan call (or the host's allocator callback) failed.
    ErrorVulkan = 3,
    /// Device or host memory ran out while the renderer made what the message names. The
    /// call changed nothing: the renderer stays usable (docs/c-and-cpp.md, "Errors").
    ErrorOutOfMemory = 4,
    /// The device was lost (the message names the call that reported it): wait for the
    /// device to be idle, destroy the renderer and make a new device (docs/c-and-cpp.md,
    /// "Errors").
    ErrorDeviceLost = 5,
    /// The library panicked (a bug): the renderer refuses every call but its destruction.
    ErrorPanic = 6,
    /// Any other failure (the message says what).
    ErrorOther = 7,
    /// Another process of the communicator failed (its own call reports why; the message
    /// names its rank): nothing was composited. Only `es_offscreen_render_composited`.
    ErrorOtherRank = 8,
}

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

/// The message of the last call on this thread that did not return `ES_STATUS_SUCCESS` (an
/// empty string if none has failed). The pointer stays valid until the next failing call on
/// this thread; copy the text to keep it. Any thread.
#[no_mangle]
pub extern "C" fn es_last_error() -> *const c_char {
    // During a thread's teardown the thread-local may be gone: an empty message then.
    LAST_ERROR
        .try_with(|message| message.borrow().as_ptr())
        .unwrap_or(c"".as_ptr())
}

/// Records `message` as this thread's last error.
fn set_last_error(message: String) {
    let message = CString::new(message.replace('\0', " ")).unwrap_or_default();
    let _ = LAST_ERROR.try_with(|last| *last.borrow_mut() = message);
}

/// A failure of a C call: the status it returns and the message it leaves.
#[derive(Debug)]
pub(crate) struct Failure {
    pub status: EsStatus,
    pub message: String,
}

impl Failure {
    /// An invalid argument `what`, because `why`.
    pub fn invalid(what: &str, why: impl std::fmt::Display) -> Self {
        Self {
            status: EsStatus::ErrorInvalidArgument,
            message: format!("invalid {what}: {why}"),
        }
    }
}

impl From<Error> for Failure {
    fn from(error: Error) -> Self {
        let status = match &error {
            Error::Invalid { .. } => EsStatus::ErrorInvalidArgument,
            Error::NoDevice(_) => EsStatus::ErrorUnsupported,
            Error::Vulkan { .. } | Error::Loader(_) | Error::Validation { .. } => {
                EsStatus::ErrorVulkan
            }
            Error::OutOfMemory { .. } => EsStatus::ErrorOutOfMemory,
            Error::Allocation { .. } => EsStatus::ErrorVulkan,
            Error::DeviceLost { .. } => EsStatus::ErrorDeviceLost,
            _ => EsStatus::ErrorOther,
        };
        Self {
            status,
            message: error.to_string(),
        }
    }
}

/// Runs `body` for the entry point `function`: its failure, or a panic, becomes the status
/// returned and this thread's last error, prefixed with the function's name.
pub(crate) fn guard(function: &str, body: impl FnOnce() -> Result<(), Failure>) -> EsStatus {
    let outcome = catch_unwind(AssertUnwindSafe(body)).unwrap_or_else(|panic| {
        let text = panic
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "no message".into());
        Err(Failure {
            status: EsStatus::ErrorPanic,
            message: format!("internal error (panic): {text}"),
        })
    });
    match outcome {
        Ok(()) => EsStatus::Success,
        Err(failure) => {
            set_last_error(format!("{function}: {}", failure.message));
            failure.status
        }
    }
}

/// The struct behind `pointer`, checked for null and for a `struct_size` at least as large as
/// the fields this library reads (`minimum`, the size of its first version).
///
/// # Safety
/// A non-null `pointer` points at a readable `T` whose first field is its `struct_size`
/// (`u32`), and `T` at least `minimum` bytes of it are valid.
pub(crate) unsafe fn versioned<'a, T>(
    pointer: *const T,
    what: &str,
    minimum: usize,
) -> Result<&'a T, Failure> {
    if pointer.is_null() {
        return Err(Failure::invalid(what, "is null"));
    }
    // SAFETY: non-null; the caller guarantees a `u32` struct_size first.
    let size = unsafe { *pointer.cast::<u32>() } as usize;
    if size < minimum {
        return Err(Failure::invalid(
            what,
            format!("struct_size is {size}, at least {minimum} (sizeof the struct) expected"),
        ));
    }
    // SAFETY: as above; the struct is at least as large as this version's fields.
    Ok(unsafe { &*pointer })
}

/// A copy of the struct behind `pointer` as far as the host's version of it goes: its first
/// `struct_size` bytes (at least `minimum`, the first version's size; at most this version's
/// whole struct) over `later()`, which gives the fields of later versions the host did not
/// allocate. Returns the copy and the bytes taken from the host.
///
/// # Safety
/// A non-null `pointer` points at a readable struct whose first field is its `struct_size`
/// (`u32`) and which holds at least `min(struct_size, size_of::<T>())` readable bytes. `T` is
/// plain data: any bytes of a host's struct are a valid `T` (integers and floats only).
pub(crate) unsafe fn versioned_prefix<T: Copy>(
    pointer: *const T,
    what: &str,
    minimum: usize,
    later: impl FnOnce() -> T,
) -> Result<(T, usize), Failure> {
    if pointer.is_null() {
        return Err(Failure::invalid(what, "is null"));
    }
    // SAFETY: non-null; the caller guarantees a `u32` struct_size first.
    let size = unsafe { pointer.cast::<u32>().read_unaligned() } as usize;
    if size < minimum {
        return Err(Failure::invalid(
            what,
            format!("struct_size is {size}, at least {minimum} (sizeof the struct) expected"),
        ));
    }
    let taken = size.min(std::mem::size_of::<T>());
    let mut copy = later();
    // SAFETY: the host's struct holds `taken` readable bytes (caller contract); `copy` is a
    // distinct local of `size_of::<T>() >= taken` bytes; `T` is plain data, so the bytes make
    // a valid `T`.
    unsafe {
        std::ptr::copy_nonoverlapping(
            pointer.cast::<u8>(),
            (&mut copy as *mut T).cast::<u8>(),
            taken,
        )
    };
    Ok((copy, taken))
}

/// The value behind a non-null `pointer`.
///
/// # Safety
/// A non-null `pointer` points at a readable `T`.
pub(crate) unsafe fn required<'a, T>(pointer: *const T, what: &str) -> Result<&'a T, Failure> {
    // SAFETY: caller contract.
    unsafe { pointer.as_ref() }.ok_or_else(|| Failure::invalid(what, "is null"))
}

/// The output slot behind a non-null `pointer`.
///
/// # Safety
/// A non-null `pointer` points at a writable `T`.
pub(crate) unsafe fn output<'a, T>(pointer: *mut T, what: &str) -> Result<&'a mut T, Failure> {
    // SAFETY: caller contract.
    unsafe { pointer.as_mut() }.ok_or_else(|| Failure::invalid(what, "is null"))
}
