/* The header compiles as C11 with every warning an error (tests/cpp_host.rs builds it with
 * -std=c11 -Wall -Wextra -Wpedantic -Werror, with the flags pkg-config gives), and the
 * object links against the installed library. */
#include <ellipsoid_splat.h>

int main(void) {
    EsCamera camera;
    const double eye[3] = {0.0, 0.0, 5.0};
    const double target[3] = {0.0, 0.0, 0.0};
    const double up[3] = {0.0, 1.0, 0.0};
    EsStatus status = es_camera_look_at(eye, target, up, 45.0, 0.1, 64, 48, &camera);
    if (status != ES_STATUS_SUCCESS || camera.width != 64 || es_abi_version() != ES_ABI_VERSION) {
        return 1;
    }
    /* A null output is an error with a message, not a crash. */
    status = es_camera_look_at(eye, target, up, 45.0, 0.1, 64, 48, NULL);
    if (status != ES_STATUS_ERROR_INVALID_ARGUMENT || es_last_error()[0] == '\0') {
        return 2;
    }
    /* The settings choose the frame plan's mode; the plan and its wisdom need a renderer. */
    EsSettings settings;
    if (es_settings_default(&settings) != ES_STATUS_SUCCESS ||
        settings.struct_size != sizeof(EsSettings) || settings.plan_mode != ES_PLAN_MODE_MEASURE) {
        return 3;
    }
    settings.plan_mode = ES_PLAN_MODE_FIXED;
    settings.fixed_path = ES_PATH_KIND_SPLAT;
    EsFramePlan plan;
    size_t size = 0;
    const uint8_t bytes[4] = {0};
    if (es_renderer_last_plan(NULL, &plan) != ES_STATUS_ERROR_INVALID_ARGUMENT ||
        es_renderer_plan_wisdom(NULL, NULL, &size) != ES_STATUS_ERROR_INVALID_ARGUMENT ||
        es_renderer_load_plan_wisdom(NULL, bytes, sizeof bytes) != ES_STATUS_ERROR_INVALID_ARGUMENT ||
        es_renderer_set_settings(NULL, &settings) != ES_STATUS_ERROR_INVALID_ARGUMENT) {
        return 4;
    }
    return 0;
}
