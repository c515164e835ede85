//! What the layer does to the calls it sees: counts those a fault can hit, and at the armed
//! one makes the device run out of memory (that call fails, later calls pass) or lose itself
//! (from that call on, every call that can report a loss reports it). Armed and read through
//! the exported `es_fault_*` functions.

use std::ffi::{c_char, CStr};
use std::sync::Mutex;

use ash::vk;

/// What kind of fault is armed (`es_fault_arm`'s `kind`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    /// `VK_ERROR_OUT_OF_DEVICE_MEMORY` from one call that makes, binds, maps, records or
    /// submits something.
    OutOfMemory,
    /// `VK_ERROR_DEVICE_LOST` from one call that can report a loss, and every such call after.
    DeviceLost,
}

/// What a call does, as far as faults go. The spec's error codes decide the classes: every
/// call here may return `VK_ERROR_OUT_OF_DEVICE_MEMORY`, but only submits, waits and queries
/// (and `vkCreateDevice`) may return `VK_ERROR_DEVICE_LOST`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Class {
    /// Makes, allocates, binds, maps or records something: can run out of memory.
    Creates,
    /// `vkCreateDevice`: can run out of memory or find the device lost.
    CreatesDevice,
    /// A queue submission: can run out of memory or report a loss.
    Submits,
    /// Waits for the device (fences, idle): reports a loss once the real wait has returned,
    /// so nothing is destroyed while the GPU still uses it. Out of memory is not injected
    /// here: the work's state after such a wait would be unknown, which no caller can mend.
    Waits,
    /// Reads the device's state (fence status, query results): reports a loss.
    Queries,
}

impl Class {
    fn hit_by(self, kind: Kind) -> bool {
        match kind {
            Kind::OutOfMemory => {
                matches!(self, Class::Creates | Class::CreatesDevice | Class::Submits)
            }
            Kind::DeviceLost => !matches!(self, Class::Creates),
        }
    }
}

/// What the intercepted call does next.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Decision {
    /// Pass the call down unchanged.
    Pass,
    /// Return this error without passing the call down.
    Fail(vk::Result),
    /// The device is lost: the class's loss behaviour (see [`Class`]).
    Lost,
}

struct State {
    kind: Kind,
    /// The eligible call (1-based) that gets the fault; 0: count only.
    at: u64,
    /// Eligible calls counted since arming.
    count: u64,
    /// Calls are neither counted nor failed (the host's own work, for a walk over the
    /// renderer's calls); a lost device stays lost.
    paused: bool,
    lost: bool,
    /// The call the fault hit, NUL-terminated for `es_fault_fired`.
    fired: Option<&'static CStr>,
}

static STATE: Mutex<State> = Mutex::new(State {
    kind: Kind::OutOfMemory,
    at: 0,
    count: 0,
    paused: true,
    lost: false,
    fired: None,
});

fn state() -> std::sync::MutexGuard<'static, State> {
    // A panic never happens with the lock held; a poisoned lock still holds valid counts.
    STATE.lock().unwrap_or_else(|p| p.into_inner())
}

/// Counts the call `name` of `class` and decides what it does.
pub(crate) fn decide(class: Class, name: &'static CStr) -> Decision {
    let mut s = state();
    if !s.paused && class.hit_by(s.kind) {
        s.count += 1;
        if s.count == s.at {
            s.fired = Some(name);
            match s.kind {
                Kind::OutOfMemory => return Decision::Fail(vk::Result::ERROR_OUT_OF_DEVICE_MEMORY),
                Kind::DeviceLost => s.lost = true,
            }
        }
    }
    if s.lost && class.hit_by(Kind::DeviceLost) {
        Decision::Lost
    } else {
        Decision::Pass
    }
}

/// Arms the layer: from now on it counts the calls a fault of `kind` (1: out of device
/// memory, 2: device lost) can hit, and the `at`-th of them (1-based; 0: none) gets the
/// fault. Clears the count, the loss and the pause. Returns 0, or -1 for an unknown kind.
#[no_mangle]
pub extern "C" fn es_fault_arm(kind: u32, at: u64) -> i32 {
    let kind = match kind {
        1 => Kind::OutOfMemory,
        2 => Kind::DeviceLost,
        _ => return -1,
    };
    let mut s = state();
    *s = State {
        kind,
        at,
        count: 0,
        paused: false,
        lost: false,
        fired: None,
    };
    0
}

/// The environment variable that arms the layer in a process no test code runs in (the
/// viewer under Xvfb): `device-lost:N` or `out-of-memory:N`, read when an instance is made.
pub(crate) const ARM_VARIABLE: &str = "ES_FAULT_ARM";

/// Arms the layer from [`ARM_VARIABLE`] if it is set and not yet armed in this process;
/// a value it cannot read leaves the layer unarmed (the test then sees no fault, and fails).
pub(crate) fn arm_from_environment() {
    static READ: std::sync::Once = std::sync::Once::new();
    READ.call_once(|| {
        let Ok(value) = std::env::var(ARM_VARIABLE) else {
            return;
        };
        let parsed = value.split_once(':').and_then(|(kind, at)| {
            let kind = match kind {
                "out-of-memory" => 1,
                "device-lost" => 2,
                _ => return None,
            };
            Some((kind, at.parse::<u64>().ok()?))
        });
        if let Some((kind, at)) = parsed {
            es_fault_arm(kind, at);
        }
    });
}

/// The calls counted since `es_fault_arm` (those its kind can hit, while not paused).
#[no_mangle]
pub extern "C" fn es_fault_count() -> u64 {
    state().count
}

/// The name of the call the fault hit, or null while it has not fired. The string is static.
#[no_mangle]
pub extern "C" fn es_fault_fired() -> *const c_char {
    state().fired.map_or(std::ptr::null(), CStr::as_ptr)
}

/// Pauses (non-zero) or resumes (0) counting and faults: a walk over the renderer's own
/// calls pauses around the host's. The layer starts paused, so it does nothing until armed.
#[no_mangle]
pub extern "C" fn es_fault_pause(paused: u32) {
    state().paused = paused != 0;
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The layer's state is the process's: one test walks through every rule.
    #[test]
    fn faults_hit_the_armed_call_of_their_classes() {
        let oom = Decision::Fail(vk::Result::ERROR_OUT_OF_DEVICE_MEMORY);
        assert_eq!(
            decide(Class::Creates, c"a"),
            Decision::Pass,
            "not armed yet"
        );
        assert_eq!(es_fault_count(), 0, "paused until armed");
        // Out of memory: the second call that can run out fails, alone; waits are not counted.
        assert_eq!(es_fault_arm(1, 2), 0);
        assert_eq!(decide(Class::Creates, c"vkCreateBuffer"), Decision::Pass);
        assert_eq!(decide(Class::Waits, c"vkWaitForFences"), Decision::Pass);
        assert_eq!(decide(Class::Submits, c"vkQueueSubmit"), oom);
        assert_eq!(decide(Class::Creates, c"vkCreateBuffer"), Decision::Pass);
        assert_eq!(es_fault_count(), 3);
        // SAFETY: a static name.
        let fired = unsafe { CStr::from_ptr(es_fault_fired()) };
        assert_eq!(fired, c"vkQueueSubmit");
        // Device lost: from the first call that can report it on, every such call does;
        // creating still works, as on a real lost device; paused calls are not counted.
        assert_eq!(es_fault_arm(2, 1), 0);
        assert!(es_fault_fired().is_null());
        assert_eq!(decide(Class::Creates, c"vkCreateBuffer"), Decision::Pass);
        es_fault_pause(1);
        assert_eq!(decide(Class::Waits, c"vkDeviceWaitIdle"), Decision::Pass);
        es_fault_pause(0);
        assert_eq!(decide(Class::Submits, c"vkQueueSubmit"), Decision::Lost);
        assert_eq!(decide(Class::Creates, c"vkCreateImage"), Decision::Pass);
        assert_eq!(
            decide(Class::Queries, c"vkGetQueryPoolResults"),
            Decision::Lost
        );
        es_fault_pause(1);
        assert_eq!(
            decide(Class::Waits, c"vkWaitForFences"),
            Decision::Lost,
            "still lost"
        );
        assert_eq!(es_fault_count(), 2);
        assert_eq!(es_fault_arm(3, 1), -1, "no such kind");
    }
}
