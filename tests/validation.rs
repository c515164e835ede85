//! The validation canary: proves that the layer is really on in tests and that its messages
//! reach the log every other test checks.

use ash::vk;
use ellipsoid_splat::{Context, ContextOptions};

#[test]
fn invalid_usage_is_reported() {
    let context = Context::new(&ContextOptions::validated()).expect("validated device");
    assert!(
        context.check_validation().is_ok(),
        "a fresh device is clean"
    );
    // A buffer with no usage flags breaks VUID-VkBufferCreateInfo-usage-requiredbitmask; the
    // driver itself accepts it, so the call is harmless apart from the report.
    let info = vk::BufferCreateInfo::default()
        .size(64)
        .usage(vk::BufferUsageFlags::empty())
        .sharing_mode(vk::SharingMode::EXCLUSIVE);
    // SAFETY: deliberately invalid usage for the validation layer to catch; the buffer is
    // destroyed right away and never bound or used.
    unsafe {
        if let Ok(buffer) = context.device().create_buffer(&info, None) {
            context.device().destroy_buffer(buffer, None);
        }
    }
    let failures = context.validation_failures();
    assert!(
        failures
            .iter()
            .any(|m| m.id_name.contains("VUID-VkBufferCreateInfo-usage")),
        "the validation layer did not report the invalid buffer usage: {failures:?}"
    );
    let err = context.check_validation().unwrap_err();
    assert!(
        err.to_string().contains("validation layer reported"),
        "{err}"
    );
}
