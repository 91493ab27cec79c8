/* A Vulkan host that shares its own VkDevice with wethair: it creates the instance and device
 * with what wethair asks for, steps the paper scene with water on that device, and draws the
 * strands straight from wethair's vertex VkBuffer with the Kajiya-Kay shaders of
 * bindings/shaders/ into an offscreen image, written as a PNG. Headless (no surface).
 *
 * Per frame: step -> wethair_sim_get_vulkan_buffer -> one submit that waits on the ready
 * timeline semaphore, draws, and signals the release semaphore that wethair's next write
 * waits for.
 *
 * usage: vulkan_host [--out FILE] [--frames N] [--particles N] [--validate] [--compare]
 *                    [--check-errors] [--fixed-step]
 *   --validate      enable VK_LAYER_KHRONOS_validation; any error it reports fails the run
 *   --compare       read the shared buffer back and require it to equal the copy path's bytes
 *   --check-errors  check the refusals: missing instance extension, device features, bad
 *                   arguments; and create/destroy a simulation on the device before the main one
 *   --fixed-step    fixed steps of 1/120 s, interpolated, advanced by 50 Hz frames
 *                   (wethair_sim_advance); the last frame is too short for a step, so the
 *                   buffer handed out must show a new blend written without a step */
#include "png.h"
#include "vk_common.h"
#include "kk_frag.h"
#include "kk_vert.h"


#define W 1280
#define H 960
#define SS 2 /* supersampling: rendered at SS*W x SS*H, averaged down for the PNG */

/* A device on queue family 0 with the given extensions and feature chain (NULL: none). */
static VkDevice make_device(const Host *h, const WetHairVulkanRequirementsInfo *info, int with_features,
                            VkDeviceCreateInfo *out_ci) {
    static float priority = 1.0f;
    static VkDeviceQueueCreateInfo qi = {.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qi.queueFamilyIndex = 0;
    qi.queueCount = 1;
    qi.pQueuePriorities = &priority;
    VkDeviceCreateInfo ci = {.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    ci.queueCreateInfoCount = 1;
    ci.pQueueCreateInfos = &qi;
    ci.enabledExtensionCount = info->device_extension_count;
    ci.ppEnabledExtensionNames = info->device_extensions;
    ci.pNext = with_features ? info->features : NULL;
    VkDevice dev = VK_NULL_HANDLE;
    vk_check(vkCreateDevice(h->phys, &ci, NULL, &dev), "vkCreateDevice");
    *out_ci = ci;
    return dev;
}

static WetHairSimDesc paper_desc(const WetHairGroom *groom, const WetHairCollider *head) {
    WetHairSimDesc desc;
    wethair_sim_desc_default(&desc);
    desc.groom = groom;
    desc.colliders = head;
    desc.collider_count = 1;
    desc.backend = WETHAIR_BACKEND_GPU;
    return desc;
}

/* Expects `r` to be `want` with a message containing `needle`; counts failures. */
/* Orders 3-float points by their bytes (any fixed order will do: it only pairs two sets). */
static int cmp_point(const void *a, const void *b) {
    return memcmp(a, b, 12);
}

static int expect(WetHairResult r, WetHairResult want, const char *needle, const char *what) {
    const char *msg = r == WETHAIR_OK ? "" : wethair_last_error_message();
    if (r != want || (needle && !strstr(msg, needle))) {
        fprintf(stderr, "check failed: %s: got %s (%s), wanted %s containing \"%s\"\n", what,
                wethair_result_string((uint32_t)r), msg, wethair_result_string((uint32_t)want), needle ? needle : "");
        return 1;
    }
    printf("refused as expected: %s: %s\n", what, msg);
    return 0;
}

/* A host loader that returns NULL for one entry (engines ship odd loaders). */
static const char *null_entry = NULL;
static PFN_vkVoidFunction VKAPI_CALL gipa_missing(VkInstance instance, const char *name) {
    if (null_entry && !strcmp(name, null_entry)) return NULL;
    return vkGetInstanceProcAddr(instance, name);
}

/* The refusals and the create/destroy cycle; returns the number of failed checks. */
static int check_errors(const Host *h, const WetHairVulkanRequirementsInfo *info, const WetHairVulkanDevice *good,
                        const WetHairGroom *groom, const WetHairCollider *head) {
    int fails = 0;
    WetHairVulkanRequirements *req = NULL;
    /* An instance description without the required instance extension. */
    WetHairVulkanDevice d = describe(h);
    d.instance_extension_count = 0;
    fails += expect(wethair_vulkan_requirements_create(&d, &req), WETHAIR_ERROR_UNSUPPORTED,
                    "VK_KHR_get_physical_device_properties2", "instance without VK_KHR_get_physical_device_properties2");
    /* A vkGetInstanceProcAddr that gives NULL for an entry wethair needs: refused by name. */
    const char *entries[] = {"vkGetPhysicalDeviceProperties2", "vkGetDeviceProcAddr"};
    for (int i = 0; i < 2; i++) {
        d = describe(h);
        d.get_instance_proc_addr = (void *)gipa_missing;
        null_entry = entries[i];
        fails += expect(wethair_vulkan_requirements_create(&d, &req), WETHAIR_ERROR_UNSUPPORTED, entries[i],
                        "vkGetInstanceProcAddr without an entry");
        null_entry = NULL;
    }
    /* Bad arguments. */
    fails += expect(wethair_vulkan_requirements_create(NULL, &req), WETHAIR_ERROR_NULL_POINTER, "host", "NULL host");
    d = describe(h);
    d.struct_size = 8;
    fails += expect(wethair_vulkan_requirements_create(&d, &req), WETHAIR_ERROR_STRUCT_SIZE, "struct_size", "bad struct_size");
    d = describe(h);
    d.queue_unlock = NULL;
    fails += expect(wethair_vulkan_requirements_create(&d, &req), WETHAIR_ERROR_INVALID_ARGUMENT, "queue_unlock",
                    "lock without unlock");
    d = describe(h);
    d.api_version = VK_API_VERSION_1_0;
    fails += expect(wethair_vulkan_requirements_create(&d, &req), WETHAIR_ERROR_UNSUPPORTED, "1.1", "Vulkan 1.0 instance");
    WetHairSimDesc desc = paper_desc(groom, head);
    WetHairSim *sim = NULL;
    fails += expect(wethair_sim_create_vulkan(&desc, NULL, &sim), WETHAIR_ERROR_NULL_POINTER, "host", "NULL host device");
    desc.backend = WETHAIR_BACKEND_CPU;
    fails += expect(wethair_sim_create_vulkan(&desc, good, &sim), WETHAIR_ERROR_INVALID_ARGUMENT, "CPU",
                    "CPU backend on a Vulkan device");
    desc.backend = WETHAIR_BACKEND_GPU;
    /* A second device made without wethair's features: refused, naming the first missing one. */
    VkDeviceCreateInfo bare_ci;
    VkDevice bare = make_device(h, info, 0, &bare_ci);
    d = *good;
    d.device = bare;
    d.enabled_features = &bare_ci;
    if (info->feature_count > 0)
        fails += expect(wethair_sim_create_vulkan(&desc, &d, &sim), WETHAIR_ERROR_UNSUPPORTED, info->feature_names[0],
                        "device without the required features");
    if (info->device_extension_count > 0) {
        d.device_extension_count = 0;
        fails += expect(wethair_sim_create_vulkan(&desc, &d, &sim), WETHAIR_ERROR_UNSUPPORTED,
                        info->device_extensions[0], "device without the required extensions");
    }
    if (sim) {
        fprintf(stderr, "check failed: a refused create wrote its output\n");
        fails++;
    }
    vkDestroyDevice(bare, NULL);
    /* A simulation made, stepped and destroyed on the shared device: the device stays usable. */
    wh_check(wethair_sim_create_vulkan(&desc, good, &sim), "wethair_sim_create_vulkan (first)");
    for (int i = 0; i < 3; i++) wh_check(wethair_sim_step(sim, 1.0f / 60.0f), "wethair_sim_step");
    WetHairVulkanBuffer vb = {0};
    vb.struct_size = sizeof vb;
    wh_check(wethair_sim_get_vulkan_buffer(sim, &vb), "wethair_sim_get_vulkan_buffer");
    /* Release the frame we did not draw, as the contract asks, then destroy. */
    VkSemaphore release = (VkSemaphore)(uintptr_t)vb.release_semaphore;
    VkSemaphoreSignalInfo si = {.sType = VK_STRUCTURE_TYPE_SEMAPHORE_SIGNAL_INFO};
    si.semaphore = release;
    si.value = vb.release_value;
    vk_check(vkSignalSemaphore(h->device, &si), "vkSignalSemaphore");
    wethair_sim_destroy(sim);
    printf("created, stepped and destroyed a first simulation on the host's device\n");
    /* A step that blows up (springs far past the explicit limit) is reported by the shared path
     * too, though this host never reads through the copy path. */
    WetHairSimDesc stiff = desc;
    stiff.stretch.stiffness = 1e9f;
    wh_check(wethair_sim_create_vulkan(&stiff, good, &sim), "wethair_sim_create_vulkan (stiff)");
    WetHairResult got = WETHAIR_OK;
    for (int i = 0; i < 30 && got == WETHAIR_OK; i++) {
        got = wethair_sim_step(sim, 1.0f / 60.0f);
        if (got != WETHAIR_OK) break;
        memset(&vb, 0, sizeof vb);
        vb.struct_size = sizeof vb;
        got = wethair_sim_get_vulkan_buffer(sim, &vb);
        if (got != WETHAIR_OK) break;
        si.semaphore = (VkSemaphore)(uintptr_t)vb.release_semaphore;
        si.value = vb.release_value;
        vk_check(vkSignalSemaphore(h->device, &si), "vkSignalSemaphore");
        vk_check(vkDeviceWaitIdle(h->device), "vkDeviceWaitIdle"); /* let the status land */
    }
    fails += expect(got, WETHAIR_ERROR_UNSTABLE, "non-finite", "a blown-up step on the shared path");
    wethair_sim_destroy(sim);
    sim = NULL;
    /* The simulation's copy-path refusal for a CPU simulation. */
    desc.backend = WETHAIR_BACKEND_CPU;
    WetHairSim *cpu = NULL;
    wh_check(wethair_sim_create(&desc, &cpu), "wethair_sim_create (cpu)");
    fails += expect(wethair_sim_get_vulkan_buffer(cpu, &vb), WETHAIR_ERROR_UNSUPPORTED, "VkBuffer",
                    "Vulkan buffer of a CPU simulation");
    WetHairVulkanWater wat = {0};
    wat.struct_size = sizeof wat;
    fails += expect(wethair_sim_get_vulkan_water(cpu, &wat), WETHAIR_ERROR_UNSUPPORTED, "water",
                    "Vulkan water of a CPU simulation");
    fails += expect(wethair_sim_get_vulkan_water(cpu, NULL), WETHAIR_ERROR_NULL_POINTER, "out", "NULL water output");
    wat.struct_size = 4;
    fails += expect(wethair_sim_get_vulkan_water(cpu, &wat), WETHAIR_ERROR_STRUCT_SIZE, "struct_size",
                    "water output with a bad struct_size");
    if (wat.buffer || wat.draw_buffer) {
        fprintf(stderr, "check failed: a refused water call wrote its output\n");
        fails++;
    }
    wethair_sim_destroy(cpu);
    return fails;
}

/* Column-major view-projection (Vulkan clip space: y down, depth 0..1) of the renderer's camera. */
static void view_proj(const float eye[3], const float at[3], float fov_deg, float aspect, float m[16]) {
    float f[3] = {at[0] - eye[0], at[1] - eye[1], at[2] - eye[2]};
    float l = sqrtf(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    for (int i = 0; i < 3; i++) f[i] /= l;
    float r[3] = {f[1], -f[0], 0.0f}; /* f x z */
    l = sqrtf(r[0] * r[0] + r[1] * r[1]);
    r[0] /= l;
    r[1] /= l;
    float u[3] = {r[1] * f[2] - r[2] * f[1], r[2] * f[0] - r[0] * f[2], r[0] * f[1] - r[1] * f[0]};
    float t = 1.0f / tanf(0.5f * fov_deg * 3.14159265f / 180.0f), n = 0.05f, fa = 5.0f;
    /* Rows of the view matrix: right, -up (Vulkan y down), forward; then perspective. */
    float rows[3][4] = {{r[0], r[1], r[2], 0}, {-u[0], -u[1], -u[2], 0}, {f[0], f[1], f[2], 0}};
    for (int i = 0; i < 3; i++) rows[i][3] = -(rows[i][0] * eye[0] + rows[i][1] * eye[1] + rows[i][2] * eye[2]);
    float a = fa / (fa - n), b = -n * fa / (fa - n);
    for (int c = 0; c < 4; c++) {
        m[4 * c + 0] = t / aspect * rows[0][c];
        m[4 * c + 1] = t * rows[1][c];
        m[4 * c + 2] = a * rows[2][c] + (c == 3 ? b : 0.0f);
        m[4 * c + 3] = rows[2][c];
    }
}

typedef struct {
    float view_proj[16];
    float eye[4];
    float light[4];
} PushConstants;

int main(int argc, char **argv) {
    const char *out = "wethair_vulkan.png";
    uint32_t frames = 120, particles = 1000;
    int validate = 0, compare = 0, errors = 0, fixed = 0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--validate")) validate = 1;
        else if (!strcmp(argv[i], "--compare")) compare = 1;
        else if (!strcmp(argv[i], "--fixed-step")) fixed = 1;
        else if (!strcmp(argv[i], "--check-errors")) errors = 1;
        else if (i + 1 < argc && !strcmp(argv[i], "--out")) out = argv[++i];
        else if (i + 1 < argc && !strcmp(argv[i], "--frames")) frames = (uint32_t)atoi(argv[++i]);
        else if (i + 1 < argc && !strcmp(argv[i], "--particles")) particles = (uint32_t)atoi(argv[++i]);
        else {
            fprintf(stderr,
                    "usage: %s [--out FILE] [--frames N] [--particles N] [--validate] [--compare] [--check-errors] "
                    "[--fixed-step]\n",
                    argv[0]);
            return 2;
        }
    }
    Host h = {0};
    char why[256];
    if (!create_instance(&h, validate, NULL, 0, why, sizeof why)) {
        fprintf(stderr, "%s\n", why);
        return 1;
    }
    uint32_t n_phys = 1;
    VkResult er = vkEnumeratePhysicalDevices(h.instance, &n_phys, &h.phys);
    if ((er != VK_SUCCESS && er != VK_INCOMPLETE) || n_phys == 0) {
        fprintf(stderr, "no Vulkan physical device (on Linux without a GPU install mesa-vulkan-drivers)\n");
        return 1;
    }
    vkGetPhysicalDeviceMemoryProperties(h.phys, &h.mem);
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(h.phys, &props);

    /* What wethair needs of a device on this physical device. */
    WetHairVulkanDevice wd = describe(&h);
    WetHairVulkanRequirements *req = NULL;
    wh_check(wethair_vulkan_requirements_create(&wd, &req), "wethair_vulkan_requirements_create");
    WetHairVulkanRequirementsInfo info = {0};
    info.struct_size = sizeof info;
    wh_check(wethair_vulkan_requirements_get_info(req, &info), "wethair_vulkan_requirements_get_info");
    printf("device: %s; wethair needs %u device extensions", props.deviceName, info.device_extension_count);
    for (uint32_t i = 0; i < info.device_extension_count; i++) printf("%s%s", i ? ", " : " (", info.device_extensions[i]);
    printf("%s and %u features\n", info.device_extension_count ? ")" : "", info.feature_count);

    VkDeviceCreateInfo dci;
    h.device = make_device(&h, &info, 1, &dci);
    vkGetDeviceQueue(h.device, 0, 0, &h.queue);
    wd.device = h.device;
    wd.device_extension_count = info.device_extension_count;
    wd.device_extensions = info.device_extensions;
    wd.enabled_features = &dci;

    WetHairGroom *groom = NULL;
    wh_check(wethair_groom_create_paper_scene(10000, 6, &groom), "wethair_groom_create_paper_scene");
    WetHairCollider head = {WETHAIR_COLLIDER_SPHERE, {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, 0.1f};
    int failed_checks = errors ? check_errors(&h, &info, &wd, groom, &head) : 0;
    WetHairSimDesc desc = paper_desc(groom, &head);
    if (fixed) {
        /* The fixed-step fields came in 0.4.0: the whole current desc, with the paper's model. */
        wh_check(wethair_sim_desc_init(&desc, sizeof desc), "wethair_sim_desc_init");
        desc.groom = groom;
        desc.colliders = &head;
        desc.collider_count = 1;
        desc.backend = WETHAIR_BACKEND_GPU;
        desc.integrator = WETHAIR_INTEGRATOR_SYMPLECTIC_EULER;
        desc.spring_model = WETHAIR_SPRING_MODEL_PER_SPRING;
        desc.fixed_step = 1.0f / 120.0f;
    }
    WetHairSim *sim = NULL;
    wh_check(wethair_sim_create_vulkan(&desc, &wd, &sim), "wethair_sim_create_vulkan");
    wethair_groom_destroy(groom);
    wethair_vulkan_requirements_destroy(req); /* the device exists: its chain is no longer read */
    wh_print_backend(sim);

    /* Layout for the pipeline, before any frame is acquired. */
    WetHairVertexLayout lay = {0};
    lay.struct_size = sizeof lay;
    wh_check(wethair_sim_get_vertex_layout(sim, &lay), "wethair_sim_get_vertex_layout");
    uint32_t per = lay.vertex_count / lay.strand_count, segs = lay.strand_count * (per - 1);
    HostBuffer index = host_buffer(&h, (VkDeviceSize)segs * 2 * sizeof(uint32_t), VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
    uint32_t *ix = index.map;
    for (uint32_t s = 0, k = 0; s < lay.strand_count; s++)
        for (uint32_t i = 0; i + 1 < per; i++) {
            ix[k++] = s * per + i;
            ix[k++] = s * per + i + 1;
        }

    /* Render pass, images, pipeline. */
    const VkFormat color_fmt = VK_FORMAT_R8G8B8A8_UNORM, depth_fmt = VK_FORMAT_D32_SFLOAT;
    Image color = image(&h, W * SS, H * SS, VK_SAMPLE_COUNT_1_BIT, color_fmt, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                        VK_IMAGE_ASPECT_COLOR_BIT);
    Image depth = image(&h, W * SS, H * SS, VK_SAMPLE_COUNT_1_BIT, depth_fmt, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, VK_IMAGE_ASPECT_DEPTH_BIT);
    VkAttachmentDescription att[2] = {{0}, {0}};
    att[0].format = color_fmt;
    att[0].samples = VK_SAMPLE_COUNT_1_BIT;
    att[0].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    att[0].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    att[0].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    att[0].stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    att[0].initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    att[0].finalLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    att[1] = att[0];
    att[1].format = depth_fmt;
    att[1].storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    att[1].finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
    VkAttachmentReference cref = {0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkAttachmentReference dref = {1, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    VkSubpassDescription sub = {0};
    sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    sub.colorAttachmentCount = 1;
    sub.pColorAttachments = &cref;
    sub.pDepthStencilAttachment = &dref;
    /* The previous frame's copy out of the colour image finishes before this frame clears it. */
    VkSubpassDependency dep = {0};
    dep.srcSubpass = VK_SUBPASS_EXTERNAL;
    dep.dstSubpass = 0;
    dep.srcStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
    dep.dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT;
    dep.srcAccessMask = VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    dep.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    VkRenderPassCreateInfo rpi = {.sType = VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    rpi.attachmentCount = 2;
    rpi.pAttachments = att;
    rpi.subpassCount = 1;
    rpi.pSubpasses = &sub;
    rpi.dependencyCount = 1;
    rpi.pDependencies = &dep;
    VkRenderPass pass;
    vk_check(vkCreateRenderPass(h.device, &rpi, NULL, &pass), "vkCreateRenderPass");
    VkImageView views[2] = {color.view, depth.view};
    VkFramebufferCreateInfo fbi = {.sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
    fbi.renderPass = pass;
    fbi.attachmentCount = 2;
    fbi.pAttachments = views;
    fbi.width = W * SS;
    fbi.height = H * SS;
    fbi.layers = 1;
    VkFramebuffer fb;
    vk_check(vkCreateFramebuffer(h.device, &fbi, NULL, &fb), "vkCreateFramebuffer");

    VkShaderModule vs = shader_module(&h, kk_vert, sizeof kk_vert), fs = shader_module(&h, kk_frag, sizeof kk_frag);
    VkPushConstantRange pcr = {VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(PushConstants)};
    VkPipelineLayoutCreateInfo pli = {.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    pli.pushConstantRangeCount = 1;
    pli.pPushConstantRanges = &pcr;
    VkPipelineLayout layout;
    vk_check(vkCreatePipelineLayout(h.device, &pli, NULL, &layout), "vkCreatePipelineLayout");
    VkVertexInputAttributeDescription attrs[3] = {
        {0, 0, VK_FORMAT_R32G32B32_SFLOAT, (uint32_t)lay.position_offset},
        {1, 0, VK_FORMAT_R32G32B32_SFLOAT, (uint32_t)lay.tangent_offset},
        {2, 0, VK_FORMAT_R32_SFLOAT, (uint32_t)lay.wetness_offset},
    };
    PipelineDesc hair = {vs, fs, VK_PRIMITIVE_TOPOLOGY_LINE_LIST, lay.stride_floats * 4, attrs, 3, 1, 0};
    VkPipeline pipe = pipeline(&h, pass, layout, VK_SAMPLE_COUNT_1_BIT, &hair);
    VkViewport vp = {0, 0, W * SS, H * SS, 0, 1};
    VkRect2D sc = {{0, 0}, {W * SS, H * SS}};

    VkCommandPoolCreateInfo cpi = {.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    cpi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    cpi.queueFamilyIndex = 0;
    VkCommandPool pool;
    vk_check(vkCreateCommandPool(h.device, &cpi, NULL, &pool), "vkCreateCommandPool");
    VkCommandBufferAllocateInfo cai = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    cai.commandPool = pool;
    cai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    cai.commandBufferCount = 1;
    VkCommandBuffer cmd;
    vk_check(vkAllocateCommandBuffers(h.device, &cai, &cmd), "vkAllocateCommandBuffers");
    VkFenceCreateInfo fci = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkFence fence;
    vk_check(vkCreateFence(h.device, &fci, NULL, &fence), "vkCreateFence");
    HostBuffer pixels = host_buffer(&h, (VkDeviceSize)W * SS * H * SS * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT);
    size_t vbytes = (size_t)lay.vertex_count * lay.stride_floats * sizeof(float);
    HostBuffer shared_copy = {0}, water_copy = {0};
    WetHairVulkanWater water = {0}, water_first = {0};
    if (compare) {
        shared_copy = host_buffer(&h, vbytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT);
        /* The water as Vulkan buffers, asked for from the first frame: every frame writes them. */
        water_copy = host_buffer(&h, (VkDeviceSize)desc.water.capacity * 16 + 16, VK_BUFFER_USAGE_TRANSFER_DST_BIT);
    }

    PushConstants pc;
    const float eye[3] = {0.05f, -0.62f, 0.22f}, at[3] = {0.0f, 0.0f, -0.02f};
    view_proj(eye, at, 40.0f, (float)W / (float)H, pc.view_proj);
    memcpy(pc.eye, eye, sizeof eye);
    pc.eye[3] = 1.0f;
    float lx = -0.4f, ly = -0.7f, lz = 0.6f, ll = sqrtf(lx * lx + ly * ly + lz * lz);
    pc.light[0] = lx / ll;
    pc.light[1] = ly / ll;
    pc.light[2] = lz / ll;
    pc.light[3] = 0.0f;

    uint32_t seed = 12345, added = 0;
    float pos[3 * 50], vel[3 * 50];
    double sim_ms = 0.0, draw_ms = 0.0;
    WetHairVulkanBuffer vb = {0};
    for (uint32_t f = 0; f < frames; f++) {
        if (added < particles) {
            uint32_t n = particles - added < 50 ? particles - added : 50;
            wh_shower(&seed, n, pos, vel);
            wh_check(wethair_sim_add_water(sim, pos, vel, n), "wethair_sim_add_water");
            added += n;
        }
        double t0 = wh_now_ms();
        if (fixed) {
            /* 50 Hz frames owe 0.4, 0.8, 0.2, 0.6, 0 of a step after theirs: the last frame's
             * 0.12 of a step never makes one. */
            float frame = f + 1 == frames && f > 0 ? 0.001f : 1.0f / 50.0f;
            WetHairAdvance adv = {0};
            adv.struct_size = sizeof adv;
            wh_check(wethair_sim_advance(sim, frame, &adv), "wethair_sim_advance");
            if (f + 1 == frames && f > 0 && adv.steps != 0) {
                fprintf(stderr, "the last frame took %u steps\n", adv.steps);
                return 1;
            }
        } else {
            wh_check(wethair_sim_step(sim, 1.0f / 60.0f), "wethair_sim_step");
        }
        double t1 = wh_now_ms();
        memset(&vb, 0, sizeof vb);
        vb.struct_size = sizeof vb;
        wh_check(wethair_sim_get_vulkan_buffer(sim, &vb), "wethair_sim_get_vulkan_buffer");
        VkBuffer shared = (VkBuffer)(uintptr_t)vb.buffer;
        int last = f + 1 == frames;
        if (compare) {
            memset(&water, 0, sizeof water);
            water.struct_size = sizeof water;
            wh_check(wethair_sim_get_vulkan_water(sim, &water), "wethair_sim_get_vulkan_water");
            if (f == 0) water_first = water;
            if (water.buffer != water_first.buffer || water.draw_buffer != water_first.draw_buffer) {
                fprintf(stderr, "the water buffers changed between frames\n");
                return 1;
            }
        }

        vk_check(vkResetCommandBuffer(cmd, 0), "vkResetCommandBuffer");
        VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        vk_check(vkBeginCommandBuffer(cmd, &bi), "vkBeginCommandBuffer");
        VkClearValue clear[2];
        clear[0].color.float32[0] = 0.36f;
        clear[0].color.float32[1] = 0.36f;
        clear[0].color.float32[2] = 0.40f;
        clear[0].color.float32[3] = 1.0f;
        clear[1].depthStencil.depth = 1.0f;
        clear[1].depthStencil.stencil = 0;
        VkRenderPassBeginInfo rbi = {.sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
        rbi.renderPass = pass;
        rbi.framebuffer = fb;
        rbi.renderArea = sc;
        rbi.clearValueCount = 2;
        rbi.pClearValues = clear;
        vkCmdBeginRenderPass(cmd, &rbi, VK_SUBPASS_CONTENTS_INLINE);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipe);
        vkCmdSetViewport(cmd, 0, 1, &vp);
        vkCmdSetScissor(cmd, 0, 1, &sc);
        vkCmdPushConstants(cmd, layout, pcr.stageFlags, 0, sizeof pc, &pc);
        VkDeviceSize voff = vb.offset;
        vkCmdBindVertexBuffers(cmd, 0, 1, &shared, &voff);
        vkCmdBindIndexBuffer(cmd, index.buf, 0, VK_INDEX_TYPE_UINT32);
        vkCmdDrawIndexed(cmd, segs * 2, 1, 0, 0, 0);
        vkCmdEndRenderPass(cmd);
        if (last) {
            VkBufferImageCopy bic = {0};
            bic.imageSubresource.aspectMask = VK_IMAGE_ASPECT_COLOR_BIT;
            bic.imageSubresource.layerCount = 1;
            bic.imageExtent.width = W * SS;
            bic.imageExtent.height = H * SS;
            bic.imageExtent.depth = 1;
            vkCmdCopyImageToBuffer(cmd, color.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, pixels.buf, 1, &bic);
            if (compare) {
                VkBufferCopy bc = {vb.offset, 0, vbytes};
                vkCmdCopyBuffer(cmd, shared, shared_copy.buf, 1, &bc);
                VkBufferCopy wc[2] = {{water.draw_offset, 0, 16}, {water.offset, 16, (VkDeviceSize)water.capacity * 16}};
                vkCmdCopyBuffer(cmd, (VkBuffer)(uintptr_t)water.draw_buffer, water_copy.buf, 1, &wc[0]);
                vkCmdCopyBuffer(cmd, (VkBuffer)(uintptr_t)water.buffer, water_copy.buf, 1, &wc[1]);
            }
            VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER};
            mb.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
            mb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
            vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &mb, 0, NULL, 0,
                                 NULL);
        }
        vk_check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
        /* Wait for wethair's write of this frame; release the buffer to its next write. */
        VkSemaphore waits[1] = {(VkSemaphore)(uintptr_t)vb.ready_semaphore};
        VkSemaphore signals[1] = {(VkSemaphore)(uintptr_t)vb.release_semaphore};
        VkPipelineStageFlags wait_stage =
            VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_VERTEX_INPUT_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
        VkTimelineSemaphoreSubmitInfo tsi = {.sType = VK_STRUCTURE_TYPE_TIMELINE_SEMAPHORE_SUBMIT_INFO};
        tsi.waitSemaphoreValueCount = 1;
        tsi.pWaitSemaphoreValues = &vb.ready_value;
        tsi.signalSemaphoreValueCount = 1;
        tsi.pSignalSemaphoreValues = &vb.release_value;
        VkSubmitInfo si = {.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO};
        si.pNext = &tsi;
        si.waitSemaphoreCount = 1;
        si.pWaitSemaphores = waits;
        si.pWaitDstStageMask = &wait_stage;
        si.commandBufferCount = 1;
        si.pCommandBuffers = &cmd;
        si.signalSemaphoreCount = 1;
        si.pSignalSemaphores = signals;
        vk_check(locked_submit(&h, &si, fence), "vkQueueSubmit");
        vk_check(vkWaitForFences(h.device, 1, &fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
        vk_check(vkResetFences(h.device, 1, &fence), "vkResetFences");
        double t2 = wh_now_ms();
        sim_ms += t1 - t0;
        draw_ms += t2 - t1;
    }

    int mismatched = 0;
    if (compare) {
        /* The same frame through the copy path: it must be the very same bytes. */
        size_t cap = (size_t)lay.vertex_count * lay.stride_floats, written = 0;
        float *copy = malloc(cap * sizeof *copy);
        if (!copy) return 1;
        wh_check(wethair_sim_get_vertex_buffer(sim, copy, cap, &written), "wethair_sim_get_vertex_buffer");
        mismatched = written != cap || memcmp(copy, shared_copy.map, vbytes) != 0;
        size_t nan = 0;
        for (size_t i = 0; i < cap; i++) nan += !isfinite(((float *)shared_copy.map)[i]);
        printf("shared VkBuffer vs copy path: %zu bytes %s, %zu non-finite\n", vbytes,
               mismatched ? "DIFFER" : "identical", nan);
        mismatched |= nan != 0;
        /* The shared water: the indirect draw's count and the particles equal the copy path's.
           The shared buffer holds them in the device's order, the copy path sorted: both are
           sorted the same way here and compared as sets. */
        const uint32_t *cmdw = water_copy.map;
        const float *wv = (const float *)water_copy.map + 4;
        size_t wcap = desc.water.capacity ? desc.water.capacity : 1;
        float *wp = malloc(sizeof(float) * 3 * wcap);
        float *ws = malloc(sizeof(float) * 3 * wcap);
        uint32_t nw = 0;
        if (!wp || !ws) return 1;
        wh_check(wethair_sim_get_water(sim, wp, desc.water.capacity, &nw), "wethair_sim_get_water");
        int water_bad = cmdw[0] != nw || cmdw[1] != 1 || cmdw[2] != 0 || cmdw[3] != 0 || nw == 0;
        for (uint32_t i = 0; i < nw && !water_bad; i++) {
            memcpy(ws + 3 * i, wv + 4 * i, 12);
            water_bad = wv[4 * i + 3] != 1.0f;
        }
        if (!water_bad) {
            qsort(ws, nw, 12, cmp_point);
            qsort(wp, nw, 12, cmp_point);
            water_bad = memcmp(ws, wp, (size_t)nw * 12) != 0;
        }
        free(ws);
        printf("shared water VkBuffers vs copy path: draw count %u, %u particles %s\n", cmdw[0], nw,
               water_bad ? "DIFFER" : "identical");
        mismatched |= water_bad;
        free(wp);
        free(copy);
    }

    /* Average SS x SS pixels down into the PNG. */
    uint8_t *img = malloc((size_t)W * H * 3);
    if (!img) return 1;
    const uint8_t *px = pixels.map;
    size_t lit = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            for (int c = 0; c < 3; c++) {
                unsigned acc = 0;
                for (int j = 0; j < SS; j++)
                    for (int i = 0; i < SS; i++) acc += px[4 * ((size_t)(y * SS + j) * W * SS + x * SS + i) + c];
                img[3 * ((size_t)y * W + x) + c] = (uint8_t)((acc + SS * SS / 2) / (SS * SS));
            }
    for (size_t i = 0; i < (size_t)W * H; i++) lit += img[3 * i] != img[3 * 1] || img[3 * i + 2] != img[3 * 1 + 2];
    if (png_write(out, img, W, H)) {
        fprintf(stderr, "could not write %s\n", out);
        return 1;
    }
    free(img);
    WetHairStats st = wh_stats(sim);
    printf("wethair %s on the host's VkDevice: %u strands x %u points, %u frames, %u particles held\n",
           wethair_version_string(), st.strands, per, frames, st.particles);
    printf("timing: step %.3f ms/frame, draw from the shared buffer %.3f ms/frame; %zu pixels show hair; wrote %s\n",
           sim_ms / frames, draw_ms / frames, lit, out);

    /* wethair first (it finishes its work on the queue), then the host's objects. */
    wethair_sim_destroy(sim);
    vkDeviceWaitIdle(h.device);
    if (compare) {
        host_buffer_free(&h, &shared_copy);
        host_buffer_free(&h, &water_copy);
    }
    host_buffer_free(&h, &pixels);
    host_buffer_free(&h, &index);
    vkDestroyFence(h.device, fence, NULL);
    vkDestroyCommandPool(h.device, pool, NULL);
    vkDestroyPipeline(h.device, pipe, NULL);
    vkDestroyPipelineLayout(h.device, layout, NULL);
    vkDestroyShaderModule(h.device, vs, NULL);
    vkDestroyShaderModule(h.device, fs, NULL);
    vkDestroyFramebuffer(h.device, fb, NULL);
    vkDestroyRenderPass(h.device, pass, NULL);
    image_free(&h, &color);
    image_free(&h, &depth);
    vkDestroyDevice(h.device, NULL);
    destroy_instance(&h);
    if (validate) printf("validation: %d errors\n", vkc_validation_errors);
    if (errors) printf("error checks: %d failed\n", failed_checks);
    if (lit < 1000) fprintf(stderr, "the image shows almost no hair (%zu pixels)\n", lit);
    return (vkc_validation_errors || failed_checks || mismatched || lit < 1000) ? 1 : 0;
}
