// A C++ host of ellipsoid-splat's C ABI, as an engine embeds it: its own Vulkan instance (with
// the validation layer and synchronization validation), device and allocator callbacks, an
// offscreen render pass in which it draws a mesh plane, the ellipsoids cutting it (a jittered
// projection from its own matrices) and a Dear ImGui window, then reads colour and depth back.
//
//   cpp_host GLYPHS.bin OUT_PREFIX full|imgui|plan
//
// GLYPHS.bin holds EsGlyph records. `full` and `imgui` write OUT_PREFIX.rgba (R8G8B8A8),
// OUT_PREFIX.depth (float32) and OUT_PREFIX.camera (the EsCamera the library made of the
// matrices, as text). `plan` checks the frame plan through the C ABI: the paths a host fixes
// draw the same picture, the plan that measures settles, its wisdom goes to a second renderer,
// and bad settings and bytes are refused. Exits 0 only if nothing failed and the validation
// layer said nothing.
#include <ellipsoid_splat.h>

#include <imgui.h>
#include <imgui_impl_vulkan.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "plane.frag.h"
#include "plane.vert.h"

namespace {

constexpr uint32_t kWidth = 320;
constexpr uint32_t kHeight = 240;
constexpr float kNear = 0.5f;
constexpr float kPlaneHalfSize = 6.0f;
// ImGui's window, fully opaque, at a fixed place (tests/cpp_host.rs compares its inside).
constexpr float kWindowX = 8, kWindowY = 8, kWindowW = 150, kWindowH = 64;

int g_messages = 0;

VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                          VkDebugUtilsMessageTypeFlagsEXT,
                                          const VkDebugUtilsMessengerCallbackDataEXT* data,
                                          void*) {
    ++g_messages;
    std::fprintf(stderr, "validation: %s\n", data->pMessage);
    return VK_FALSE;
}

void check(VkResult result, const char* what) {
    if (result != VK_SUCCESS) {
        throw std::runtime_error(std::string(what) + " failed: " + std::to_string(result));
    }
}

void check(EsStatus status, const char* what) {
    if (status != ES_STATUS_SUCCESS) {
        throw std::runtime_error(std::string(what) + ": " + es_last_error());
    }
}

void check_imgui(VkResult result) { check(result, "ImGui Vulkan backend"); }

void expect(bool ok, const std::string& what) {
    if (!ok) throw std::runtime_error(what);
}

// A call that must fail with `status` and a message holding `words`.
void refused(EsStatus got, EsStatus want, const char* words, const std::string& what) {
    if (got != want || std::strstr(es_last_error(), words) == nullptr)
        throw std::runtime_error(what + " was not refused as expected (status " +
                                 std::to_string(got) + "): " + es_last_error());
}

const char* path_name(uint32_t kind) {
    switch (kind) {
        case ES_PATH_KIND_NONE: return "none";
        case ES_PATH_KIND_DRAW: return "draw";
        case ES_PATH_KIND_SPLAT: return "splat";
        case ES_PATH_KIND_VISIBLE_FIRST: return "visible-first";
        default: return "?";
    }
}

// Column-major 4x4 matrices, as GLSL and most engines keep them.
struct Mat4 {
    float m[16] = {};
    float& at(int row, int col) { return m[col * 4 + row]; }
    float at(int row, int col) const { return m[col * 4 + row]; }
};

Mat4 multiply(const Mat4& a, const Mat4& b) {
    Mat4 r;
    for (int row = 0; row < 4; ++row)
        for (int col = 0; col < 4; ++col)
            for (int k = 0; k < 4; ++k) r.at(row, col) += a.at(row, k) * b.at(k, col);
    return r;
}

// A right-handed view looking from eye at target.
Mat4 look_at(const float eye[3], const float target[3], const float up[3]) {
    float f[3] = {target[0] - eye[0], target[1] - eye[1], target[2] - eye[2]};
    float fl = std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    for (float& v : f) v /= fl;
    float s[3] = {f[1] * up[2] - f[2] * up[1], f[2] * up[0] - f[0] * up[2],
                  f[0] * up[1] - f[1] * up[0]};
    float sl = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    for (float& v : s) v /= sl;
    float u[3] = {s[1] * f[2] - s[2] * f[1], s[2] * f[0] - s[0] * f[2], s[0] * f[1] - s[1] * f[0]};
    Mat4 v;
    for (int i = 0; i < 3; ++i) {
        v.at(0, i) = s[i];
        v.at(1, i) = u[i];
        v.at(2, i) = -f[i];
    }
    v.at(0, 3) = -(s[0] * eye[0] + s[1] * eye[1] + s[2] * eye[2]);
    v.at(1, 3) = -(u[0] * eye[0] + u[1] * eye[1] + u[2] * eye[2]);
    v.at(2, 3) = f[0] * eye[0] + f[1] * eye[1] + f[2] * eye[2];
    v.at(3, 3) = 1;
    return v;
}

// Vulkan clip space (y down), reversed Z with an infinite far plane, jittered by (dx, dy)
// pixels: pixel (i, j) samples the unjittered image at (i + 0.5 + dx, j + 0.5 + dy).
Mat4 jittered_projection(float fov_y_rad, float dx, float dy) {
    float f = 1.0f / std::tan(0.5f * fov_y_rad);
    Mat4 p;
    p.at(0, 0) = f * kHeight / kWidth;
    p.at(1, 1) = -f;
    p.at(2, 3) = kNear;
    p.at(3, 2) = -1;
    Mat4 jitter;
    for (int i = 0; i < 4; ++i) jitter.at(i, i) = 1;
    jitter.at(0, 3) = -2.0f * dx / kWidth;
    jitter.at(1, 3) = -2.0f * dy / kHeight;
    return multiply(jitter, p);
}

// The host's allocator: one dedicated allocation per buffer, as simple as an engine's could
// be; the library calls it for every buffer it makes.
struct HostAllocator {
    VkDevice device = VK_NULL_HANDLE;
    VkPhysicalDeviceMemoryProperties properties{};
    int live = 0;

    uint32_t memory_type(uint32_t bits, VkMemoryPropertyFlags want) const {
        for (uint32_t i = 0; i < properties.memoryTypeCount; ++i)
            if ((bits & (1u << i)) && (properties.memoryTypes[i].propertyFlags & want) == want)
                return i;
        return UINT32_MAX;
    }

    static VkResult create(void* user, const VkBufferCreateInfo* info, EsMemoryUse use,
                           const char* /*name*/, EsBuffer* out) {
        auto* self = static_cast<HostAllocator*>(user);
        VkResult r = vkCreateBuffer(self->device, info, nullptr, &out->buffer);
        if (r != VK_SUCCESS) return r;
        VkMemoryRequirements req;
        vkGetBufferMemoryRequirements(self->device, out->buffer, &req);
        VkMemoryPropertyFlags want = use == ES_MEMORY_USE_GPU_ONLY
                                         ? VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT
                                         : VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                               VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
        uint32_t type = self->memory_type(req.memoryTypeBits, want);
        if (type == UINT32_MAX && use == ES_MEMORY_USE_GPU_ONLY)
            type = self->memory_type(req.memoryTypeBits, 0);
        VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
        alloc.allocationSize = req.size;
        alloc.memoryTypeIndex = type;
        VkDeviceMemory memory = VK_NULL_HANDLE;
        r = type == UINT32_MAX ? VK_ERROR_OUT_OF_DEVICE_MEMORY
                               : vkAllocateMemory(self->device, &alloc, nullptr, &memory);
        if (r == VK_SUCCESS) r = vkBindBufferMemory(self->device, out->buffer, memory, 0);
        out->mapped = nullptr;
        if (r == VK_SUCCESS && use != ES_MEMORY_USE_GPU_ONLY)
            r = vkMapMemory(self->device, memory, 0, VK_WHOLE_SIZE, 0, &out->mapped);
        if (r != VK_SUCCESS) {
            vkDestroyBuffer(self->device, out->buffer, nullptr);
            vkFreeMemory(self->device, memory, nullptr);
            return r;
        }
        out->allocation = reinterpret_cast<void*>(memory);
        out->size = req.size;
        ++self->live;
        return VK_SUCCESS;
    }

    static void destroy(void* user, const EsBuffer* buffer) {
        auto* self = static_cast<HostAllocator*>(user);
        vkDestroyBuffer(self->device, buffer->buffer, nullptr);
        vkFreeMemory(self->device, reinterpret_cast<VkDeviceMemory>(buffer->allocation), nullptr);
        --self->live;
    }
};

// An image or buffer of the host's own, with dedicated memory.
struct Owned {
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkImage image = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
    VkBuffer buffer = VK_NULL_HANDLE;
    void* mapped = nullptr;
};

class Host {
  public:
    Host();
    ~Host();
    void run(const std::vector<EsGlyph>& glyphs, const std::string& out, bool full);
    void plans(const std::vector<EsGlyph>& glyphs);

  private:
    // A frame's colour and depth as read back.
    struct Pixels {
        std::vector<uint8_t> rgba;
        std::vector<float> depth;
    };
    void create_device();
    Owned image(VkFormat format, VkImageUsageFlags usage, VkImageAspectFlags aspect);
    Owned readback(VkDeviceSize size);
    void create_pass();
    void create_plane_pipeline();
    void init_imgui();
    VkCommandBuffer begin();
    void submit(VkCommandBuffer cmd);
    EsRenderer* make_renderer(const EsSettings* settings);
    EsCamera make_camera(Mat4* clip_from_world) const;
    Pixels frame(EsRenderer* renderer, const std::vector<EsGlyph>* upload,
                 const EsCamera& camera, const Mat4& clip_from_world, bool imgui);
    void same(const Pixels& a, const Pixels& b, const char* what) const;

    VkInstance instance_ = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
    VkPhysicalDevice physical_ = VK_NULL_HANDLE;
    VkDevice device_ = VK_NULL_HANDLE;
    uint32_t family_ = 0;
    uint32_t features_ = 0;
    bool splat_ = false;     // the compute splat's features are enabled
    bool lavapipe_ = false;  // Mesa's CPU driver: every path's frame is the same bit for bit
    VkQueue queue_ = VK_NULL_HANDLE;
    VkCommandPool pool_ = VK_NULL_HANDLE;
    HostAllocator allocator_;
    Owned color_, depth_, color_read_, depth_read_;
    VkRenderPass pass_ = VK_NULL_HANDLE;
    VkFramebuffer framebuffer_ = VK_NULL_HANDLE;
    VkPipelineLayout plane_layout_ = VK_NULL_HANDLE;
    VkPipeline plane_ = VK_NULL_HANDLE;
    VkDescriptorPool imgui_pool_ = VK_NULL_HANDLE;
    bool imgui_ = false;
};

Host::Host() {
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "ellipsoid-splat C++ host";
    app.apiVersion = VK_API_VERSION_1_3;
    const char* layers[] = {"VK_LAYER_KHRONOS_validation"};
    const char* extensions[] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME};
    VkValidationFeatureEnableEXT enables[] = {
        VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
    VkValidationFeaturesEXT validation{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
    validation.enabledValidationFeatureCount = 1;
    validation.pEnabledValidationFeatures = enables;
    VkDebugUtilsMessengerCreateInfoEXT messenger{
        VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    messenger.pNext = &validation;
    messenger.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    messenger.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                            VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                            VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    messenger.pfnUserCallback = on_message;
    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pNext = &messenger;
    info.pApplicationInfo = &app;
    info.enabledLayerCount = 1;
    info.ppEnabledLayerNames = layers;
    info.enabledExtensionCount = 1;
    info.ppEnabledExtensionNames = extensions;
    check(vkCreateInstance(&info, nullptr, &instance_), "vkCreateInstance");
    auto create_messenger = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
    messenger.pNext = nullptr;  // the validation features belong to the instance only
    check(create_messenger(instance_, &messenger, nullptr, &messenger_),
          "vkCreateDebugUtilsMessengerEXT");
    create_device();
    create_pass();
    create_plane_pipeline();
}

void Host::create_device() {
    uint32_t count = 0;
    vkEnumeratePhysicalDevices(instance_, &count, nullptr);
    if (count == 0) throw std::runtime_error("no Vulkan device");
    std::vector<VkPhysicalDevice> devices(count);
    vkEnumeratePhysicalDevices(instance_, &count, devices.data());
    physical_ = devices[0];
    VkPhysicalDeviceProperties properties;
    vkGetPhysicalDeviceProperties(physical_, &properties);
    lavapipe_ = std::strncmp(properties.deviceName, "llvmpipe", 8) == 0;
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &count, families.data());
    family_ = UINT32_MAX;
    for (uint32_t i = 0; i < count; ++i)
        if ((families[i].queueFlags & (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT)) ==
            (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT)) {
            family_ = i;
            break;
        }
    if (family_ == UINT32_MAX) throw std::runtime_error("no graphics and compute queue");

    // What the renderer's target needs (a render pass: no dynamic rendering), and the compute
    // splat's features where the device has them.
    VkFormat color_format = VK_FORMAT_R8G8B8A8_UNORM;
    EsTargetInfo target{sizeof(EsTargetInfo)};
    target.render_pass = reinterpret_cast<VkRenderPass>(uintptr_t{1});  // any non-null pass
    target.color_attachment_count = 1;
    target.color_formats = &color_format;
    target.depth_format = VK_FORMAT_D32_SFLOAT;
    target.samples = 1;
    check(es_target_required_features(&target, &features_), "es_target_required_features");
    VkPhysicalDeviceVulkan12Features has12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceFeatures2 has{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &has12};
    vkGetPhysicalDeviceFeatures2(physical_, &has);
    bool splat = has.features.shaderInt64 && has12.shaderBufferInt64Atomics;
    if (splat) features_ |= ES_FEATURE_SHADER_INT64 | ES_FEATURE_SHADER_BUFFER_INT64_ATOMICS;
    splat_ = splat;

    VkPhysicalDeviceVulkan13Features on13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    on13.maintenance4 = (features_ & ES_FEATURE_MAINTENANCE4) != 0;
    on13.dynamicRendering = (features_ & ES_FEATURE_DYNAMIC_RENDERING) != 0;
    VkPhysicalDeviceVulkan12Features on12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES,
                                          &on13};
    on12.shaderBufferInt64Atomics = splat;
    VkPhysicalDeviceFeatures2 on{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &on12};
    on.features.shaderInt64 = splat;
    on.features.sampleRateShading = (features_ & ES_FEATURE_SAMPLE_RATE_SHADING) != 0;
    float priority = 1.0f;
    VkDeviceQueueCreateInfo queue{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queue.queueFamilyIndex = family_;
    queue.queueCount = 1;
    queue.pQueuePriorities = &priority;
    VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &on};
    info.queueCreateInfoCount = 1;
    info.pQueueCreateInfos = &queue;
    check(vkCreateDevice(physical_, &info, nullptr, &device_), "vkCreateDevice");
    vkGetDeviceQueue(device_, family_, 0, &queue_);
    VkCommandPoolCreateInfo pool{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pool.queueFamilyIndex = family_;
    check(vkCreateCommandPool(device_, &pool, nullptr, &pool_), "vkCreateCommandPool");
    allocator_.device = device_;
    vkGetPhysicalDeviceMemoryProperties(physical_, &allocator_.properties);
}

Owned Host::image(VkFormat format, VkImageUsageFlags usage, VkImageAspectFlags aspect) {
    Owned o;
    VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = format;
    info.extent = {kWidth, kHeight, 1};
    info.mipLevels = 1;
    info.arrayLayers = 1;
    info.samples = VK_SAMPLE_COUNT_1_BIT;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = usage;
    check(vkCreateImage(device_, &info, nullptr, &o.image), "vkCreateImage");
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(device_, o.image, &req);
    VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    alloc.allocationSize = req.size;
    alloc.memoryTypeIndex =
        allocator_.memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    check(vkAllocateMemory(device_, &alloc, nullptr, &o.memory), "vkAllocateMemory");
    check(vkBindImageMemory(device_, o.image, o.memory, 0), "vkBindImageMemory");
    VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    view.image = o.image;
    view.viewType = VK_IMAGE_VIEW_TYPE_2D;
    view.format = format;
    view.subresourceRange = {aspect, 0, 1, 0, 1};
    check(vkCreateImageView(device_, &view, nullptr, &o.view), "vkCreateImageView");
    return o;
}

Owned Host::readback(VkDeviceSize size) {
    Owned o;
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = size;
    info.usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    EsBuffer b{};
    check(HostAllocator::create(&allocator_, &info, ES_MEMORY_USE_READBACK, "readback", &b),
          "readback buffer");
    --allocator_.live;  // the host's own, not the renderer's
    o.buffer = b.buffer;
    o.memory = reinterpret_cast<VkDeviceMemory>(b.allocation);
    o.mapped = b.mapped;
    return o;
}

void Host::create_pass() {
    color_ = image(VK_FORMAT_R8G8B8A8_UNORM,
                   VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                   VK_IMAGE_ASPECT_COLOR_BIT);
    depth_ = image(VK_FORMAT_D32_SFLOAT,
                   VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                   VK_IMAGE_ASPECT_DEPTH_BIT);
    color_read_ = readback(4ull * kWidth * kHeight);
    depth_read_ = readback(4ull * kWidth * kHeight);

    VkAttachmentDescription attachments[2] = {};
    attachments[0].format = VK_FORMAT_R8G8B8A8_UNORM;
    attachments[1].format = VK_FORMAT_D32_SFLOAT;
    for (auto& a : attachments) {
        a.samples = VK_SAMPLE_COUNT_1_BIT;
        a.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
        a.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
        a.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
        a.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
        a.finalLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    }
    VkAttachmentReference color{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkAttachmentReference depth{1, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    VkSubpassDescription subpass{};
    subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    subpass.colorAttachmentCount = 1;
    subpass.pColorAttachments = &color;
    subpass.pDepthStencilAttachment = &depth;
    VkPipelineStageFlags attachment_stages = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT |
                                             VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT |
                                             VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
    VkSubpassDependency dependencies[2] = {};
    dependencies[0].srcSubpass = VK_SUBPASS_EXTERNAL;
    dependencies[0].dstSubpass = 0;
    dependencies[0].srcStageMask = attachment_stages | VK_PIPELINE_STAGE_TRANSFER_BIT;
    dependencies[0].dstStageMask = attachment_stages;
    dependencies[0].srcAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
    dependencies[0].dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT |
                                    VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                                    VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    dependencies[1].srcSubpass = 0;
    dependencies[1].dstSubpass = VK_SUBPASS_EXTERNAL;
    dependencies[1].srcStageMask = attachment_stages;
    dependencies[1].dstStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
    dependencies[1].srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT |
                                    VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    dependencies[1].dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
    VkRenderPassCreateInfo info{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    info.attachmentCount = 2;
    info.pAttachments = attachments;
    info.subpassCount = 1;
    info.pSubpasses = &subpass;
    info.dependencyCount = 2;
    info.pDependencies = dependencies;
    check(vkCreateRenderPass(device_, &info, nullptr, &pass_), "vkCreateRenderPass");
    VkImageView views[2] = {color_.view, depth_.view};
    VkFramebufferCreateInfo fb{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
    fb.renderPass = pass_;
    fb.attachmentCount = 2;
    fb.pAttachments = views;
    fb.width = kWidth;
    fb.height = kHeight;
    fb.layers = 1;
    check(vkCreateFramebuffer(device_, &fb, nullptr, &framebuffer_), "vkCreateFramebuffer");
}

void Host::create_plane_pipeline() {
    VkShaderModule modules[2];
    const uint32_t* code[2] = {plane_vert, plane_frag};
    size_t sizes[2] = {sizeof(plane_vert), sizeof(plane_frag)};
    for (int i = 0; i < 2; ++i) {
        VkShaderModuleCreateInfo m{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
        m.codeSize = sizes[i];
        m.pCode = code[i];
        check(vkCreateShaderModule(device_, &m, nullptr, &modules[i]), "vkCreateShaderModule");
    }
    VkPushConstantRange range{VK_SHADER_STAGE_VERTEX_BIT, 0, 68};
    VkPipelineLayoutCreateInfo layout{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layout.pushConstantRangeCount = 1;
    layout.pPushConstantRanges = &range;
    check(vkCreatePipelineLayout(device_, &layout, nullptr, &plane_layout_),
          "vkCreatePipelineLayout");
    VkPipelineShaderStageCreateInfo stages[2] = {};
    for (int i = 0; i < 2; ++i) {
        stages[i].sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
        stages[i].stage = i == 0 ? VK_SHADER_STAGE_VERTEX_BIT : VK_SHADER_STAGE_FRAGMENT_BIT;
        stages[i].module = modules[i];
        stages[i].pName = "main";
    }
    VkPipelineVertexInputStateCreateInfo input{
        VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    VkPipelineInputAssemblyStateCreateInfo assembly{
        VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    assembly.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    viewport.viewportCount = 1;
    viewport.scissorCount = 1;
    VkPipelineRasterizationStateCreateInfo raster{
        VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    raster.polygonMode = VK_POLYGON_MODE_FILL;
    raster.cullMode = VK_CULL_MODE_NONE;
    raster.lineWidth = 1.0f;
    VkPipelineMultisampleStateCreateInfo multisample{
        VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
    VkPipelineDepthStencilStateCreateInfo depth{
        VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    depth.depthTestEnable = VK_TRUE;
    depth.depthWriteEnable = VK_TRUE;
    depth.depthCompareOp = VK_COMPARE_OP_GREATER;  // reversed Z
    VkPipelineColorBlendAttachmentState blend{};
    blend.colorWriteMask = 0xf;
    VkPipelineColorBlendStateCreateInfo blending{
        VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    blending.attachmentCount = 1;
    blending.pAttachments = &blend;
    VkDynamicState dynamic_states[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
    dynamic.dynamicStateCount = 2;
    dynamic.pDynamicStates = dynamic_states;
    VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
    info.stageCount = 2;
    info.pStages = stages;
    info.pVertexInputState = &input;
    info.pInputAssemblyState = &assembly;
    info.pViewportState = &viewport;
    info.pRasterizationState = &raster;
    info.pMultisampleState = &multisample;
    info.pDepthStencilState = &depth;
    info.pColorBlendState = &blending;
    info.pDynamicState = &dynamic;
    info.layout = plane_layout_;
    info.renderPass = pass_;
    check(vkCreateGraphicsPipelines(device_, VK_NULL_HANDLE, 1, &info, nullptr, &plane_),
          "vkCreateGraphicsPipelines");
    for (VkShaderModule m : modules) vkDestroyShaderModule(device_, m, nullptr);
}

VkCommandBuffer Host::begin() {
    VkCommandBufferAllocateInfo info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    info.commandPool = pool_;
    info.commandBufferCount = 1;
    VkCommandBuffer cmd;
    check(vkAllocateCommandBuffers(device_, &info, &cmd), "vkAllocateCommandBuffers");
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    check(vkBeginCommandBuffer(cmd, &begin), "vkBeginCommandBuffer");
    return cmd;
}

void Host::submit(VkCommandBuffer cmd) {
    check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd;
    check(vkQueueSubmit(queue_, 1, &submit, VK_NULL_HANDLE), "vkQueueSubmit");
    check(vkQueueWaitIdle(queue_), "vkQueueWaitIdle");
    vkFreeCommandBuffers(device_, pool_, 1, &cmd);
}

void Host::init_imgui() {
    VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 4};
    VkDescriptorPoolCreateInfo pool{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pool.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
    pool.maxSets = 4;
    pool.poolSizeCount = 1;
    pool.pPoolSizes = &size;
    check(vkCreateDescriptorPool(device_, &pool, nullptr, &imgui_pool_), "vkCreateDescriptorPool");
    ImGui::CreateContext();
    imgui_ = true;
    ImGui::StyleColorsDark();
    ImGui::GetStyle().Colors[ImGuiCol_WindowBg].w = 1.0f;  // opaque: its inside is its own
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;
    io.DisplaySize = ImVec2(float(kWidth), float(kHeight));
    io.DeltaTime = 1.0f / 60.0f;
    ImGui_ImplVulkan_InitInfo info{};
    info.Instance = instance_;
    info.PhysicalDevice = physical_;
    info.Device = device_;
    info.QueueFamily = family_;
    info.Queue = queue_;
    info.DescriptorPool = imgui_pool_;
    info.Subpass = 0;
    info.MinImageCount = 2;
    info.ImageCount = 2;
    info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
    info.CheckVkResultFn = check_imgui;
    if (!ImGui_ImplVulkan_Init(&info, pass_)) throw std::runtime_error("ImGui_ImplVulkan_Init");
    VkCommandBuffer cmd = begin();
    ImGui_ImplVulkan_CreateFontsTexture(cmd);
    submit(cmd);
    ImGui_ImplVulkan_DestroyFontUploadObjects();
}

// The renderer, on the host's device, in the host's render pass, on the host's memory.
EsRenderer* Host::make_renderer(const EsSettings* settings) {
    EsDeviceInfo device{sizeof(EsDeviceInfo)};
    device.get_instance_proc_addr = vkGetInstanceProcAddr;
    device.instance = instance_;
    device.physical_device = physical_;
    device.device = device_;
    device.queue_family_index = family_;
    device.enabled_features = features_;
    EsTargetInfo target{sizeof(EsTargetInfo)};
    target.render_pass = pass_;
    target.subpass = 0;
    target.color_attachment_count = 1;
    target.depth_format = VK_FORMAT_D32_SFLOAT;
    target.samples = 1;
    EsAllocatorCallbacks callbacks{sizeof(EsAllocatorCallbacks)};
    callbacks.user_data = &allocator_;
    callbacks.create_buffer = HostAllocator::create;
    callbacks.destroy_buffer = HostAllocator::destroy;
    EsRendererCreateInfo create{sizeof(EsRendererCreateInfo)};
    create.device = &device;
    create.target = &target;
    create.allocator = &callbacks;
    create.settings = settings;
    create.frames_in_flight = 1;
    EsRenderer* renderer = nullptr;
    check(es_renderer_create(&create, &renderer), "es_renderer_create");
    return renderer;
}

// The host's camera: its own view and a jittered reversed-Z projection.
EsCamera Host::make_camera(Mat4* clip_from_world) const {
    const float eye[3] = {3.0f, 4.0f, 9.0f}, centre[3] = {0.0f, 0.0f, 0.0f}, up[3] = {0, 1, 0};
    Mat4 view = look_at(eye, centre, up);
    Mat4 projection = jittered_projection(0.8f, 0.37f, -0.21f);
    EsCamera camera;
    check(es_camera_from_matrices(view.m, projection.m, EsViewport{0, 0, kWidth, kHeight},
                                  &camera),
          "es_camera_from_matrices");
    *clip_from_world = multiply(projection, view);
    return camera;
}

// One frame, submitted and waited for: with a renderer, its pre-pass (after uploading
// `upload`, if given) outside the pass and, in the pass, the plane and the ellipsoids; then
// ImGui's window if asked; colour and depth read back.
Host::Pixels Host::frame(EsRenderer* renderer, const std::vector<EsGlyph>* upload,
                         const EsCamera& camera, const Mat4& clip_from_world, bool imgui) {
    VkCommandBuffer cmd = begin();
    if (renderer) {
        check(es_renderer_begin_frame(renderer, 0), "es_renderer_begin_frame");
        if (upload)
            check(es_renderer_upload(renderer, cmd, upload->data(), upload->size()),
                  "es_renderer_upload");
        check(es_renderer_record_prepass(renderer, cmd, &camera), "es_renderer_record_prepass");
    }
    VkClearValue clears[2] = {};
    clears[0].color = {{0.0f, 0.0f, 0.0f, 1.0f}};
    clears[1].depthStencil = {0.0f, 0};  // reversed Z: far is 0
    VkRenderPassBeginInfo begin_pass{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    begin_pass.renderPass = pass_;
    begin_pass.framebuffer = framebuffer_;
    begin_pass.renderArea = {{0, 0}, {kWidth, kHeight}};
    begin_pass.clearValueCount = 2;
    begin_pass.pClearValues = clears;
    vkCmdBeginRenderPass(cmd, &begin_pass, VK_SUBPASS_CONTENTS_INLINE);
    if (renderer) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, plane_);
        VkViewport viewport{0, 0, float(kWidth), float(kHeight), 0, 1};
        VkRect2D scissor{{0, 0}, {kWidth, kHeight}};
        vkCmdSetViewport(cmd, 0, 1, &viewport);
        vkCmdSetScissor(cmd, 0, 1, &scissor);
        float push[17];
        std::memcpy(push, clip_from_world.m, sizeof(clip_from_world.m));
        push[16] = kPlaneHalfSize;
        vkCmdPushConstants(cmd, plane_layout_, VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(push), push);
        vkCmdDraw(cmd, 6, 1, 0, 0);
        check(es_renderer_record(renderer, cmd, &camera), "es_renderer_record");
    }
    // ImGui binds its own state, after the renderer's, as the header says a host must.
    if (imgui) ImGui_ImplVulkan_RenderDrawData(ImGui::GetDrawData(), cmd);
    vkCmdEndRenderPass(cmd);
    VkBufferImageCopy copy{};
    copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    copy.imageExtent = {kWidth, kHeight, 1};
    vkCmdCopyImageToBuffer(cmd, color_.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                           color_read_.buffer, 1, &copy);
    copy.imageSubresource.aspectMask = VK_IMAGE_ASPECT_DEPTH_BIT;
    vkCmdCopyImageToBuffer(cmd, depth_.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                           depth_read_.buffer, 1, &copy);
    VkMemoryBarrier to_host{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    to_host.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    to_host.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1,
                         &to_host, 0, nullptr, 0, nullptr);
    submit(cmd);

    size_t pixels = size_t(kWidth) * kHeight;
    Pixels out;
    const auto* rgba = static_cast<const uint8_t*>(color_read_.mapped);
    const auto* depth = static_cast<const float*>(depth_read_.mapped);
    out.rgba.assign(rgba, rgba + 4 * pixels);
    out.depth.assign(depth, depth + pixels);
    return out;
}

void Host::run(const std::vector<EsGlyph>& glyphs, const std::string& out, bool full) {
    init_imgui();
    EsSettings settings;
    check(es_settings_default(&settings), "es_settings_default");
    settings.material.specular = 0.0f;
    EsRenderer* renderer = make_renderer(&settings);
    Mat4 clip_from_world;
    EsCamera camera = make_camera(&clip_from_world);

    ImGui_ImplVulkan_NewFrame();
    ImGui::NewFrame();
    ImGui::SetNextWindowPos(ImVec2(kWindowX, kWindowY));
    ImGui::SetNextWindowSize(ImVec2(kWindowW, kWindowH));
    ImGui::Begin("ellipsoid-splat", nullptr,
                 ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoMove |
                     ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings);
    ImGui::Text("%zu glyphs", glyphs.size());
    ImGui::End();
    ImGui::Render();

    Pixels pixels = frame(full ? renderer : nullptr, &glyphs, camera, clip_from_world, true);
    std::ofstream(out + ".rgba", std::ios::binary)
        .write(reinterpret_cast<const char*>(pixels.rgba.data()),
               std::streamsize(pixels.rgba.size()));
    std::ofstream(out + ".depth", std::ios::binary)
        .write(reinterpret_cast<const char*>(pixels.depth.data()),
               std::streamsize(pixels.depth.size() * sizeof(float)));
    std::FILE* text = std::fopen((out + ".camera").c_str(), "w");
    if (!text) throw std::runtime_error("cannot write " + out + ".camera");
    std::fprintf(text,
                 "%u %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g "
                 "%.17g %.17g %.17g %u %u %.17g %.17g %u %.17g\n",
                 camera.projection, camera.eye[0], camera.eye[1], camera.eye[2],
                 camera.target[0], camera.target[1], camera.target[2], camera.up[0],
                 camera.up[1], camera.up[2], camera.intrinsics[0], camera.intrinsics[1],
                 camera.intrinsics[2], camera.intrinsics[3], camera.near, camera.fov_y_deg,
                 camera.width, camera.height, camera.jitter[0], camera.jitter[1],
                 camera.depth_reversed, camera.depth_far);
    std::fclose(text);

    uint64_t memory = 0;
    check(es_renderer_gpu_memory_bytes(renderer, &memory), "es_renderer_gpu_memory_bytes");
    std::printf("renderer memory: %llu bytes in %d host allocations\n",
                static_cast<unsigned long long>(memory), allocator_.live);
    check(es_renderer_destroy(renderer), "es_renderer_destroy");
    if (allocator_.live != 0)
        throw std::runtime_error("the renderer left " + std::to_string(allocator_.live) +
                                 " buffers allocated");
    // The library refuses what it cannot use, with a message, and never crashes.
    if (es_renderer_record(nullptr, VK_NULL_HANDLE, &camera) != ES_STATUS_ERROR_INVALID_ARGUMENT ||
        std::strstr(es_last_error(), "renderer") == nullptr)
        throw std::runtime_error("a null renderer was not refused");
}

// Two frames of paths that must agree: bit for bit on lavapipe; elsewhere the differing
// pixels are counted and printed (a driver may round the paths' stages differently).
void Host::same(const Pixels& a, const Pixels& b, const char* what) const {
    size_t differ = 0, first = SIZE_MAX;
    for (size_t k = 0; k < a.depth.size(); ++k) {
        bool same_pixel = std::memcmp(&a.rgba[4 * k], &b.rgba[4 * k], 4) == 0 &&
                          std::memcmp(&a.depth[k], &b.depth[k], sizeof(float)) == 0;
        if (!same_pixel && differ++ == 0) first = k;
    }
    std::printf("%s: %zu pixels differ from the draw's\n", what, differ);
    if (lavapipe_ && differ != 0)
        throw std::runtime_error(std::string(what) + ": " + std::to_string(differ) +
                                 " pixels differ from the draw's, the first at (" +
                                 std::to_string(first % kWidth) + ", " +
                                 std::to_string(first / kWidth) + ")");
}

void Host::plans(const std::vector<EsGlyph>& glyphs) {
    EsSettings settings;
    check(es_settings_default(&settings), "es_settings_default");
    expect(settings.struct_size == sizeof(EsSettings) &&
               settings.plan_mode == ES_PLAN_MODE_MEASURE &&
               settings.fixed_path == ES_PATH_KIND_NONE && settings.compute_splat == 1,
           "the default settings measure");
    settings.plan_mode = ES_PLAN_MODE_FIXED;
    settings.fixed_path = ES_PATH_KIND_DRAW;
    EsRenderer* renderer = make_renderer(&settings);
    EsFramePlan plan;
    refused(es_renderer_last_plan(renderer, &plan), ES_STATUS_ERROR_INVALID_ARGUMENT,
            "no frame", "a last plan before any frame");
    uint32_t can_measure = 0;
    check(es_renderer_can_measure(renderer, &can_measure), "es_renderer_can_measure");
    Mat4 clip_from_world;
    EsCamera camera = make_camera(&clip_from_world);

    // Each path a host fixes draws the same picture.
    Pixels drawn = frame(renderer, &glyphs, camera, clip_from_world, false);
    check(es_renderer_last_plan(renderer, &plan), "es_renderer_last_plan");
    expect(plan.struct_size == sizeof(EsFramePlan) && plan.path == ES_PATH_KIND_DRAW &&
               plan.hidden_layers == ES_HIDDEN_LAYERS_NONE && plan.compute_splat == 0 &&
               plan.measured_ms < 0 && plan.runner_up == ES_PATH_KIND_NONE,
           "the fixed draw's plan");
    expect(splat_ ? plan.reason == ES_PLAN_REASON_KIND_FIXED && plan.drawn_because == nullptr
                  : plan.reason == ES_PLAN_REASON_KIND_ONLY && plan.drawn_because != nullptr,
           "the fixed draw's reason");
    if (splat_) {
        settings.fixed_path = ES_PATH_KIND_SPLAT;
        check(es_renderer_set_settings(renderer, &settings), "es_renderer_set_settings");
        Pixels splatted = frame(renderer, nullptr, camera, clip_from_world, false);
        check(es_renderer_last_plan(renderer, &plan), "es_renderer_last_plan");
        expect(plan.path == ES_PATH_KIND_SPLAT && plan.compute_splat == 1 &&
                   plan.hidden_layers == ES_HIDDEN_LAYERS_SPLAT_ALL &&
                   plan.reason == ES_PLAN_REASON_KIND_FIXED && plan.prepass == 1,
               "the fixed splat's plan");
        same(drawn, splatted, "the splat");
        // The visible-first splat: its first still frame stamps what it shows, the next
        // splats that first.
        settings.fixed_path = ES_PATH_KIND_VISIBLE_FIRST;
        check(es_renderer_set_settings(renderer, &settings), "es_renderer_set_settings");
        const uint32_t layers[2] = {ES_HIDDEN_LAYERS_STAMP_SHOWN, ES_HIDDEN_LAYERS_VISIBLE_FIRST};
        for (uint32_t want : layers) {
            Pixels pixels = frame(renderer, nullptr, camera, clip_from_world, false);
            check(es_renderer_last_plan(renderer, &plan), "es_renderer_last_plan");
            expect(plan.path == ES_PATH_KIND_VISIBLE_FIRST && plan.hidden_layers == want &&
                       plan.visible_first == (want == ES_HIDDEN_LAYERS_VISIBLE_FIRST),
                   "the fixed visible-first splat's plan (hidden layers " +
                       std::to_string(plan.hidden_layers) + ")");
            same(drawn, pixels,
                 want == ES_HIDDEN_LAYERS_STAMP_SHOWN ? "the stamping splat"
                                                      : "the visible-first splat");
        }
    }

    // The plan that measures: the same camera until its scene class settles, which puts the
    // class in the plan's wisdom (every trial is bounded, so a device with timestamps
    // settles within a few dozen frames). A fresh renderer's wisdom holds nothing.
    EsRenderer* second = make_renderer(nullptr);
    size_t empty = 0, size = 0;
    check(es_renderer_plan_wisdom(second, nullptr, &empty), "es_renderer_plan_wisdom");
    settings.plan_mode = ES_PLAN_MODE_MEASURE;
    settings.fixed_path = ES_PATH_KIND_NONE;
    check(es_renderer_set_settings(renderer, &settings), "es_renderer_set_settings");
    int frames = 0;
    bool settled = false;
    while (frames < 90 && !settled) {
        frame(renderer, nullptr, camera, clip_from_world, false);
        ++frames;
        check(es_renderer_plan_wisdom(renderer, nullptr, &size), "es_renderer_plan_wisdom");
        settled = size > empty;
    }
    expect(settled || !can_measure, "the plan has timestamps but settled nothing in 90 frames");
    // The frame after settling is planned as measured.
    same(drawn, frame(renderer, nullptr, camera, clip_from_world, false), "the measured path");
    check(es_renderer_last_plan(renderer, &plan), "es_renderer_last_plan");
    const uint32_t learned = plan.path;
    if (settled) {
        std::printf("settled after %d frames: %s %.3f ms, runner-up %s %.3f ms\n", frames,
                    path_name(plan.path), plan.measured_ms, path_name(plan.runner_up),
                    plan.runner_up_ms);
        expect(plan.reason == ES_PLAN_REASON_KIND_MEASURED && plan.measured_ms >= 0 &&
                   (plan.runner_up == ES_PATH_KIND_NONE) == (plan.runner_up_ms < 0),
               "the measured plan: reason " + std::to_string(plan.reason));
    } else {
        std::printf("no timestamps: the plan estimated (%s)\n", path_name(plan.path));
    }

    // Its wisdom, in two calls; a buffer too small is refused with the size it needs.
    check(es_renderer_plan_wisdom(renderer, nullptr, &size), "es_renderer_plan_wisdom");
    std::vector<uint8_t> wisdom(size);
    size_t room = size - 1;
    refused(es_renderer_plan_wisdom(renderer, wisdom.data(), &room),
            ES_STATUS_ERROR_INVALID_ARGUMENT, std::to_string(size).c_str(),
            "a wisdom buffer one byte short");
    expect(room == size, "the size needed after a short buffer");
    check(es_renderer_plan_wisdom(renderer, wisdom.data(), &room), "es_renderer_plan_wisdom");
    std::printf("plan wisdom: %zu bytes (%zu with nothing learned)\n", size, empty);

    // The second renderer, on the same device, takes it in and gives the same bytes back;
    // its frames of the learned class take the learned path without exploring.
    check(es_renderer_load_plan_wisdom(second, wisdom.data(), wisdom.size()),
          "es_renderer_load_plan_wisdom");
    std::vector<uint8_t> again(size + 16);
    room = again.size();
    check(es_renderer_plan_wisdom(second, again.data(), &room), "es_renderer_plan_wisdom");
    again.resize(room);
    expect(again == wisdom, "the second renderer's wisdom differs from what it loaded");
    frame(second, &glyphs, camera, clip_from_world, false);  // a moving camera's class
    Pixels learned_frame = frame(second, nullptr, camera, clip_from_world, false);
    check(es_renderer_last_plan(second, &plan), "es_renderer_last_plan");
    if (settled)
        expect(plan.reason == ES_PLAN_REASON_KIND_MEASURED && plan.path == learned,
               "the loaded wisdom's plan: " + std::string(path_name(plan.path)) + ", reason " +
                   std::to_string(plan.reason));
    same(drawn, learned_frame, "the loaded path");

    // Bytes that are not wisdom, cut short or damaged are refused and change nothing.
    const char garbage[] = "these bytes are not what a renderer learned";
    refused(es_renderer_load_plan_wisdom(second, reinterpret_cast<const uint8_t*>(garbage),
                                         sizeof(garbage)),
            ES_STATUS_ERROR_INVALID_ARGUMENT, "plan wisdom", "garbage wisdom");
    refused(es_renderer_load_plan_wisdom(second, wisdom.data(), wisdom.size() - 1),
            ES_STATUS_ERROR_INVALID_ARGUMENT, "plan wisdom", "truncated wisdom");
    std::vector<uint8_t> damaged = wisdom;
    damaged[damaged.size() / 2] ^= 0x40;
    refused(es_renderer_load_plan_wisdom(second, damaged.data(), damaged.size()),
            ES_STATUS_ERROR_INVALID_ARGUMENT, "plan wisdom", "damaged wisdom");
    refused(es_renderer_load_plan_wisdom(second, nullptr, 8), ES_STATUS_ERROR_INVALID_ARGUMENT,
            "bytes", "null wisdom bytes");

    // Settings naming no mode or path are refused and change nothing.
    EsSettings bad = settings;
    bad.plan_mode = 7;
    refused(es_renderer_set_settings(second, &bad), ES_STATUS_ERROR_INVALID_ARGUMENT,
            "plan_mode", "plan_mode 7");
    bad.plan_mode = ES_PLAN_MODE_FIXED;
    bad.fixed_path = ES_PATH_KIND_NONE;
    refused(es_renderer_set_settings(second, &bad), ES_STATUS_ERROR_INVALID_ARGUMENT,
            "fixed_path", "ES_PLAN_MODE_FIXED without a path");
    bad.fixed_path = 42;
    refused(es_renderer_set_settings(second, &bad), ES_STATUS_ERROR_INVALID_ARGUMENT,
            "fixed_path", "fixed_path 42");
    frame(second, nullptr, camera, clip_from_world, false);
    check(es_renderer_last_plan(second, &plan), "es_renderer_last_plan");
    expect(plan.reason != ES_PLAN_REASON_KIND_FIXED, "a refused setting changed the plan");

    check(es_renderer_destroy(second), "es_renderer_destroy");
    check(es_renderer_destroy(renderer), "es_renderer_destroy");
    if (allocator_.live != 0)
        throw std::runtime_error("the renderers left " + std::to_string(allocator_.live) +
                                 " buffers allocated");
}

Host::~Host() {
    if (device_) vkDeviceWaitIdle(device_);
    if (imgui_) {
        ImGui_ImplVulkan_Shutdown();
        ImGui::DestroyContext();
    }
    auto destroy = [&](Owned& o) {
        if (o.view) vkDestroyImageView(device_, o.view, nullptr);
        if (o.image) vkDestroyImage(device_, o.image, nullptr);
        if (o.buffer) vkDestroyBuffer(device_, o.buffer, nullptr);
        if (o.memory) vkFreeMemory(device_, o.memory, nullptr);
    };
    if (device_) {
        vkDestroyDescriptorPool(device_, imgui_pool_, nullptr);
        vkDestroyPipeline(device_, plane_, nullptr);
        vkDestroyPipelineLayout(device_, plane_layout_, nullptr);
        vkDestroyFramebuffer(device_, framebuffer_, nullptr);
        vkDestroyRenderPass(device_, pass_, nullptr);
        for (Owned* o : {&color_, &depth_, &color_read_, &depth_read_}) destroy(*o);
        vkDestroyCommandPool(device_, pool_, nullptr);
        vkDestroyDevice(device_, nullptr);
    }
    if (messenger_) {
        auto destroy_messenger = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
        destroy_messenger(instance_, messenger_, nullptr);
    }
    if (instance_) vkDestroyInstance(instance_, nullptr);
}

}  // namespace

int main(int argc, char** argv) {
    const std::string mode = argc == 4 ? argv[3] : "";
    if (mode != "full" && mode != "imgui" && mode != "plan") {
        std::fprintf(stderr, "usage: %s GLYPHS.bin OUT_PREFIX full|imgui|plan\n", argv[0]);
        return 2;
    }
    if (es_abi_version() != ES_ABI_VERSION) {
        std::fprintf(stderr, "library ABI %u, header ABI %u\n", es_abi_version(), ES_ABI_VERSION);
        return 1;
    }
    std::ifstream file(argv[1], std::ios::binary | std::ios::ate);
    if (!file) {
        std::fprintf(stderr, "cannot read %s\n", argv[1]);
        return 1;
    }
    std::vector<EsGlyph> glyphs(size_t(file.tellg()) / sizeof(EsGlyph));
    file.seekg(0);
    file.read(reinterpret_cast<char*>(glyphs.data()), std::streamsize(glyphs.size() * sizeof(EsGlyph)));
    try {
        Host host;
        if (mode == "plan")
            host.plans(glyphs);
        else
            host.run(glyphs, argv[2], mode == "full");
    } catch (const std::exception& e) {
        std::fprintf(stderr, "cpp_host: %s\n", e.what());
        return 1;
    }
    std::printf("%d validation message(s)\n", g_messages);
    return g_messages == 0 ? 0 : 3;
}
