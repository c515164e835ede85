/* Embedding ellipsoid-splat in a C engine: the renderer on the engine's device, render pass and
 * VMA-style allocator, and one frame of a jittered camera from the engine's own matrices. */
#include <ellipsoid_splat.h>
#include <stdio.h>
#include <stdlib.h>

/* The engine's allocator: here plain Vulkan calls; with VMA, vmaCreateBuffer/vmaDestroyBuffer. */
typedef struct Engine {
    VkInstance instance;
    VkPhysicalDevice physical_device;
    VkDevice device;
    uint32_t queue_family;
    uint32_t enabled_features; /* the ES_FEATURE_* bits it enabled on the device */
    VkRenderPass pass;         /* colour R8G8B8A8 and depth D32_SFLOAT, subpass 0 */
    VkResult (*create_buffer)(void *, const VkBufferCreateInfo *, EsMemoryUse, const char *,
                              EsBuffer *);
    void (*destroy_buffer)(void *, const EsBuffer *);
} Engine;

static int failed(EsStatus status, const char *what) {
    if (status == ES_STATUS_SUCCESS) return 0;
    fprintf(stderr, "%s: %s\n", what, es_last_error());
    return 1;
}

/* Once: the features the pass needs go into vkCreateDevice; then the renderer. */
uint32_t engine_needs(VkRenderPass pass) {
    VkFormat color = VK_FORMAT_R8G8B8A8_UNORM;
    EsTargetInfo target = {sizeof(EsTargetInfo), pass, 0, 1, &color, VK_FORMAT_D32_SFLOAT, 1, 0};
    uint32_t features = 0;
    return failed(es_target_required_features(&target, &features), "features") ? 0 : features;
}

EsRenderer *engine_make_renderer(Engine *engine) {
    EsDeviceInfo device = {sizeof(EsDeviceInfo), vkGetInstanceProcAddr, engine->instance,
                           engine->physical_device, engine->device, engine->queue_family,
                           engine->enabled_features};
    EsTargetInfo target = {sizeof(EsTargetInfo), engine->pass, 0, 1, NULL,
                           VK_FORMAT_D32_SFLOAT, 1, 0};
    EsAllocatorCallbacks allocator = {sizeof(EsAllocatorCallbacks), engine,
                                      engine->create_buffer, engine->destroy_buffer};
    EsRendererCreateInfo info = {sizeof(EsRendererCreateInfo), &device, &target, &allocator,
                                 NULL /* default settings */, 2 /* frames in flight */,
                                 VK_NULL_HANDLE};
    EsRenderer *renderer = NULL;
    return failed(es_renderer_create(&info, &renderer), "create") ? NULL : renderer;
}

/* Every frame, after waiting for slot `slot`'s fence: the glyphs (when they changed) and the
 * pre-pass outside the pass, the draw inside it, between the engine's own draws. */
int engine_record_frame(EsRenderer *renderer, VkCommandBuffer cmd, uint32_t slot,
                        const EsGlyph *glyphs, size_t count, const float view[16],
                        const float jittered_projection[16], uint32_t width, uint32_t height,
                        void (*begin_pass)(VkCommandBuffer), void (*end_pass)(VkCommandBuffer)) {
    EsCamera camera;
    EsViewport viewport = {0, 0, width, (int32_t)height};
    if (failed(es_camera_from_matrices(view, jittered_projection, viewport, &camera), "camera") ||
        failed(es_renderer_begin_frame(renderer, slot), "begin frame") ||
        (glyphs && failed(es_renderer_upload(renderer, cmd, glyphs, count), "upload")) ||
        failed(es_renderer_record_prepass(renderer, cmd, &camera), "pre-pass"))
        return 1;
    begin_pass(cmd); /* the engine begins its render pass and draws its meshes */
    if (failed(es_renderer_record(renderer, cmd, &camera), "draw")) return 1;
    end_pass(cmd); /* the engine rebinds its own state for what it draws next */
    return 0;
}

/* The frame plan times the exact paths on the engine's own frames and keeps the fastest. What
 * it learned, saved at exit and loaded into the next run's renderer, spares it the exploring
 * (bytes from another device or driver are refused, and the plan learns anew). */
int engine_save_plan_wisdom(EsRenderer *renderer, FILE *file) {
    size_t size = 0;
    if (failed(es_renderer_plan_wisdom(renderer, NULL, &size), "wisdom size")) return 1;
    uint8_t *bytes = malloc(size);
    int bad = !bytes || failed(es_renderer_plan_wisdom(renderer, bytes, &size), "wisdom") ||
              fwrite(bytes, 1, size, file) != size;
    free(bytes);
    return bad;
}

void engine_load_plan_wisdom(EsRenderer *renderer, const uint8_t *bytes, size_t size) {
    failed(es_renderer_load_plan_wisdom(renderer, bytes, size), "wisdom (learning anew)");
}

/* Once the GPU is idle: everything the renderer made goes back to the engine's allocator. */
void engine_destroy_renderer(EsRenderer *renderer) {
    failed(es_renderer_destroy(renderer), "destroy");
}
