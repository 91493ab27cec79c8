/* Vulkan helpers shared by the C hosts that put wethair on their own VkDevice (vulkan_host.c,
 * the viewer's Vulkan renderer): error checks, the validation callback, the queue lock handed
 * to wethair, host-visible buffers, images, the instance made with wethair's requirements,
 * and the WetHairVulkanDevice that describes the host to wethair. */
#ifndef WETHAIR_EXAMPLE_VK_COMMON_H
#define WETHAIR_EXAMPLE_VK_COMMON_H

#include <pthread.h>
#include <vulkan/vulkan.h>

#include "scene.h"

#define VKC_MAX_INSTANCE_EXTS 16

/* Validation errors reported so far (warnings are printed, not counted). */
static int vkc_validation_errors = 0;

static inline void vk_check(VkResult r, const char *what) {
    if (r != VK_SUCCESS) {
        fprintf(stderr, "%s failed: VkResult %d\n", what, (int)r);
        exit(1);
    }
}

static VKAPI_ATTR VkBool32 VKAPI_CALL vkc_on_validation(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                        VkDebugUtilsMessageTypeFlagsEXT type,
                                                        const VkDebugUtilsMessengerCallbackDataEXT *data, void *user) {
    (void)type;
    (void)user;
    if (!(severity & (VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT)))
        return VK_FALSE;
    const char *msg = data->pMessage ? data->pMessage : "";
    /* Debian's layer 1.3.239 misreads WGSL debug info (DESIGN.md): a known false report. */
    if (strstr(msg, "InconsistentSpirv") && strstr(msg, "operand: 10")) return VK_FALSE;
    fprintf(stderr, "validation %s: %s\n", severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT ? "error" : "warning",
            msg);
    if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) vkc_validation_errors++;
    return VK_FALSE;
}

/* The host's queue lock, handed to wethair (these hosts are single-threaded, engines are not). */
static pthread_mutex_t vkc_queue_mutex = PTHREAD_MUTEX_INITIALIZER;
static void vkc_queue_lock(void *user) { pthread_mutex_lock((pthread_mutex_t *)user); }
static void vkc_queue_unlock(void *user) { pthread_mutex_unlock((pthread_mutex_t *)user); }

typedef struct {
    VkInstance instance;
    VkPhysicalDevice phys;
    VkDevice device;
    VkQueue queue;
    uint32_t queue_family;
    VkDebugUtilsMessengerEXT messenger;
    uint32_t api_version;
    const char *instance_exts[VKC_MAX_INSTANCE_EXTS];
    uint32_t instance_ext_count;
    VkPhysicalDeviceMemoryProperties mem;
} Host;

static inline uint32_t memory_type(const Host *h, uint32_t bits, VkMemoryPropertyFlags want) {
    for (uint32_t i = 0; i < h->mem.memoryTypeCount; i++)
        if ((bits & (1u << i)) && (h->mem.memoryTypes[i].propertyFlags & want) == want) return i;
    fprintf(stderr, "no memory type with flags 0x%x\n", (unsigned)want);
    exit(1);
}

/* Memory for `req` of a type with the `want` properties. */
static inline VkDeviceMemory allocate(const Host *h, const VkMemoryRequirements *req, VkMemoryPropertyFlags want) {
    VkMemoryAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    ai.allocationSize = req->size;
    ai.memoryTypeIndex = memory_type(h, req->memoryTypeBits, want);
    VkDeviceMemory mem;
    vk_check(vkAllocateMemory(h->device, &ai, NULL, &mem), "vkAllocateMemory");
    return mem;
}

/* A buffer in host-visible, coherent memory, mapped for its lifetime. */
typedef struct {
    VkBuffer buf;
    VkDeviceMemory mem;
    void *map;
    VkDeviceSize size;
} HostBuffer;

static inline HostBuffer host_buffer(const Host *h, VkDeviceSize size, VkBufferUsageFlags usage) {
    HostBuffer b = {0};
    b.size = size;
    VkBufferCreateInfo bi = {.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bi.size = size;
    bi.usage = usage;
    vk_check(vkCreateBuffer(h->device, &bi, NULL, &b.buf), "vkCreateBuffer");
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(h->device, b.buf, &req);
    b.mem = allocate(h, &req, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    vk_check(vkBindBufferMemory(h->device, b.buf, b.mem, 0), "vkBindBufferMemory");
    vk_check(vkMapMemory(h->device, b.mem, 0, VK_WHOLE_SIZE, 0, &b.map), "vkMapMemory");
    return b;
}

static inline void host_buffer_free(const Host *h, HostBuffer *b) {
    if (b->buf) vkDestroyBuffer(h->device, b->buf, NULL);
    if (b->mem) vkFreeMemory(h->device, b->mem, NULL);
    memset(b, 0, sizeof *b);
}

typedef struct {
    VkImage image;
    VkDeviceMemory mem;
    VkImageView view;
} Image;

/* A 2D device-local image with its view. */
static inline Image image(const Host *h, uint32_t width, uint32_t height, VkSampleCountFlagBits samples, VkFormat format,
                          VkImageUsageFlags usage, VkImageAspectFlags aspect) {
    Image im = {0};
    VkImageCreateInfo ii = {.sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    ii.imageType = VK_IMAGE_TYPE_2D;
    ii.format = format;
    ii.extent.width = width;
    ii.extent.height = height;
    ii.extent.depth = 1;
    ii.mipLevels = 1;
    ii.arrayLayers = 1;
    ii.samples = samples;
    ii.tiling = VK_IMAGE_TILING_OPTIMAL;
    ii.usage = usage;
    vk_check(vkCreateImage(h->device, &ii, NULL, &im.image), "vkCreateImage");
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(h->device, im.image, &req);
    im.mem = allocate(h, &req, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    vk_check(vkBindImageMemory(h->device, im.image, im.mem, 0), "vkBindImageMemory");
    VkImageViewCreateInfo vi = {.sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    vi.image = im.image;
    vi.viewType = VK_IMAGE_VIEW_TYPE_2D;
    vi.format = format;
    vi.subresourceRange.aspectMask = aspect;
    vi.subresourceRange.levelCount = 1;
    vi.subresourceRange.layerCount = 1;
    vk_check(vkCreateImageView(h->device, &vi, NULL, &im.view), "vkCreateImageView");
    return im;
}

static inline void image_free(const Host *h, Image *im) {
    if (im->view) vkDestroyImageView(h->device, im->view, NULL);
    if (im->image) vkDestroyImage(h->device, im->image, NULL);
    if (im->mem) vkFreeMemory(h->device, im->mem, NULL);
    memset(im, 0, sizeof *im);
}

/* A shader module from SPIR-V words embedded at build time. */
static inline VkShaderModule shader_module(const Host *h, const uint32_t *code, size_t bytes) {
    VkShaderModuleCreateInfo smi = {.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    smi.codeSize = bytes;
    smi.pCode = code;
    VkShaderModule m;
    vk_check(vkCreateShaderModule(h->device, &smi, NULL, &m), "vkCreateShaderModule");
    return m;
}

typedef struct {
    VkShaderModule vs, fs;
    VkPrimitiveTopology topology;
    uint32_t stride;
    const VkVertexInputAttributeDescription *attrs;
    uint32_t attr_count;
    int depth_test, dynamic_line_width;
} PipelineDesc;

/* A graphics pipeline of one vertex binding, no blending, viewport and scissor set per
 * command buffer (and the line width, when asked), for `pass` at `samples`. */
static inline VkPipeline pipeline(const Host *h, VkRenderPass pass, VkPipelineLayout layout,
                                  VkSampleCountFlagBits samples, const PipelineDesc *p) {
    VkPipelineShaderStageCreateInfo stages[2] = {{.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO},
                                                 {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO}};
    stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
    stages[0].module = p->vs;
    stages[0].pName = "main";
    stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
    stages[1].module = p->fs;
    stages[1].pName = "main";
    VkVertexInputBindingDescription bind = {0, p->stride, VK_VERTEX_INPUT_RATE_VERTEX};
    VkPipelineVertexInputStateCreateInfo vin = {.sType = VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    vin.vertexBindingDescriptionCount = 1;
    vin.pVertexBindingDescriptions = &bind;
    vin.vertexAttributeDescriptionCount = p->attr_count;
    vin.pVertexAttributeDescriptions = p->attrs;
    VkPipelineInputAssemblyStateCreateInfo ia = {.sType = VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    ia.topology = p->topology;
    VkPipelineViewportStateCreateInfo vps = {.sType = VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    vps.viewportCount = 1;
    vps.scissorCount = 1;
    VkPipelineRasterizationStateCreateInfo rs = {.sType = VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    rs.polygonMode = VK_POLYGON_MODE_FILL;
    rs.cullMode = VK_CULL_MODE_NONE;
    rs.lineWidth = 1.0f;
    VkPipelineMultisampleStateCreateInfo ms = {.sType = VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    ms.rasterizationSamples = samples;
    VkPipelineDepthStencilStateCreateInfo ds = {.sType = VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    ds.depthTestEnable = p->depth_test ? VK_TRUE : VK_FALSE;
    ds.depthWriteEnable = p->depth_test ? VK_TRUE : VK_FALSE;
    ds.depthCompareOp = VK_COMPARE_OP_LESS;
    VkPipelineColorBlendAttachmentState cba = {0};
    cba.colorWriteMask = 0xf;
    VkPipelineColorBlendStateCreateInfo cb = {.sType = VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    cb.attachmentCount = 1;
    cb.pAttachments = &cba;
    VkDynamicState dyn[3] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR, VK_DYNAMIC_STATE_LINE_WIDTH};
    VkPipelineDynamicStateCreateInfo dsi = {.sType = VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
    dsi.dynamicStateCount = p->dynamic_line_width ? 3 : 2;
    dsi.pDynamicStates = dyn;
    VkGraphicsPipelineCreateInfo gpi = {.sType = VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
    gpi.stageCount = 2;
    gpi.pStages = stages;
    gpi.pVertexInputState = &vin;
    gpi.pInputAssemblyState = &ia;
    gpi.pViewportState = &vps;
    gpi.pRasterizationState = &rs;
    gpi.pMultisampleState = &ms;
    gpi.pDepthStencilState = &ds;
    gpi.pColorBlendState = &cb;
    gpi.pDynamicState = &dsi;
    gpi.layout = layout;
    gpi.renderPass = pass;
    VkPipeline pipe;
    vk_check(vkCreateGraphicsPipelines(h->device, VK_NULL_HANDLE, 1, &gpi, NULL, &pipe), "vkCreateGraphicsPipelines");
    return pipe;
}

/* Creates the instance with wethair's instance requirements, the host's own `extra`
 * extensions (a window system's surface extensions) and, when asked, the validation layer.
 * Returns 0 with the reason in `why` when the loader cannot give what wethair needs. */
static inline int create_instance(Host *h, int validate, const char *const *extra, uint32_t extra_count, char *why,
                                  size_t why_len) {
    WetHairVulkanInstanceRequirements ir = {0};
    ir.struct_size = sizeof ir;
    wh_check(wethair_vulkan_get_instance_requirements(&ir), "wethair_vulkan_get_instance_requirements");
    /* The instance is made with exactly the reported apiVersion: a 1.1 or later loader accepts
     * it whatever the device offers (a 1.0 loader refuses any apiVersion above 1.0). */
    uint32_t loader = VK_API_VERSION_1_0;
    vkEnumerateInstanceVersion(&loader);
    if (loader < VK_API_VERSION_1_1) {
        snprintf(why, why_len, "the Vulkan loader offers %u.%u; wethair needs a 1.1 or later loader",
                 VK_API_VERSION_MAJOR(loader), VK_API_VERSION_MINOR(loader));
        return 0;
    }
    h->api_version = ir.min_api_version;
    h->instance_ext_count = 0;
    for (uint32_t i = 0; i < ir.extension_count && h->instance_ext_count < VKC_MAX_INSTANCE_EXTS - 1; i++)
        h->instance_exts[h->instance_ext_count++] = ir.extensions[i];
    for (uint32_t i = 0; i < extra_count && h->instance_ext_count < VKC_MAX_INSTANCE_EXTS - 1; i++)
        h->instance_exts[h->instance_ext_count++] = extra[i];
    if (validate) h->instance_exts[h->instance_ext_count++] = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
    VkApplicationInfo app = {.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "wethair example host";
    app.apiVersion = h->api_version;
    const char *layers[] = {"VK_LAYER_KHRONOS_validation"};
    VkDebugUtilsMessengerCreateInfoEXT mi = {.sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    mi.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    mi.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                     VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    mi.pfnUserCallback = vkc_on_validation;
    VkInstanceCreateInfo ci = {.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ci.pApplicationInfo = &app;
    ci.enabledExtensionCount = h->instance_ext_count;
    ci.ppEnabledExtensionNames = h->instance_exts;
    if (validate) {
        ci.enabledLayerCount = 1;
        ci.ppEnabledLayerNames = layers;
        ci.pNext = &mi; /* also covers instance creation and destruction */
    }
    VkResult r = vkCreateInstance(&ci, NULL, &h->instance);
    if (r != VK_SUCCESS) {
        snprintf(why, why_len, "vkCreateInstance failed: VkResult %d", (int)r);
        return 0;
    }
    if (validate) {
        PFN_vkCreateDebugUtilsMessengerEXT create =
            (PFN_vkCreateDebugUtilsMessengerEXT)vkGetInstanceProcAddr(h->instance, "vkCreateDebugUtilsMessengerEXT");
        vk_check(create ? create(h->instance, &mi, NULL, &h->messenger) : VK_ERROR_EXTENSION_NOT_PRESENT,
                 "vkCreateDebugUtilsMessengerEXT");
    }
    return 1;
}

/* Destroys the messenger and the instance (the device first, by the caller). */
static inline void destroy_instance(Host *h) {
    if (h->messenger) {
        PFN_vkDestroyDebugUtilsMessengerEXT destroy =
            (PFN_vkDestroyDebugUtilsMessengerEXT)vkGetInstanceProcAddr(h->instance, "vkDestroyDebugUtilsMessengerEXT");
        if (destroy) destroy(h->instance, h->messenger, NULL);
    }
    if (h->instance) vkDestroyInstance(h->instance, NULL);
    h->messenger = VK_NULL_HANDLE;
    h->instance = VK_NULL_HANDLE;
}

/* The host description wethair reads; `device` and its lists are filled once it exists. */
static inline WetHairVulkanDevice describe(const Host *h) {
    WetHairVulkanDevice d;
    wethair_vulkan_device_default(&d);
    d.api_version = h->api_version;
    d.get_instance_proc_addr = (void *)vkGetInstanceProcAddr;
    d.instance = h->instance;
    d.physical_device = h->phys;
    d.instance_extension_count = h->instance_ext_count;
    d.instance_extensions = h->instance_exts;
    d.queue_family_index = h->queue_family;
    d.queue_index = 0;
    d.queue_lock = vkc_queue_lock;
    d.queue_unlock = vkc_queue_unlock;
    d.queue_user_data = &vkc_queue_mutex;
    return d;
}

/* Submits under the queue lock that wethair also takes. */
static inline VkResult locked_submit(const Host *h, const VkSubmitInfo *si, VkFence fence) {
    vkc_queue_lock(&vkc_queue_mutex);
    VkResult r = vkQueueSubmit(h->queue, 1, si, fence);
    vkc_queue_unlock(&vkc_queue_mutex);
    return r;
}

#endif
