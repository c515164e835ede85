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
    return status == ES_STATUS_ERROR_INVALID_ARGUMENT && es_last_error()[0] != '\0' ? 0 : 2;
}
