/* The viewer's Vulkan renderer: the zero-copy path. The viewer makes its own VkInstance and
 * VkDevice with what wethair asks for (plus a swapchain), creates GPU simulations on that
 * device, and draws the strands straight from wethair's vertex VkBuffer: each frame's submit
 * waits on wethair's `ready` timeline value and signals its `release` value. The water is
 * drawn the same way, from wethair's positions with its indirect draw's count: no frame
 * crosses host memory. A CPU simulation (B switches) is drawn from host-visible buffers
 * that the copy path fills.
 * Strands are depth-tested lines (wide where the device allows) with the Kajiya-Kay shaders
 * of bindings/shaders, water points and the overlay with viewer_flat.{vert,frag}; 4x MSAA in
 * a person's window. One frame in flight: the draw figure is the frame's whole GPU cost. */
#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include "viewer.h"
#include "vk_common.h"
#include "flat_frag.h"
#include "flat_vert.h"
#include "kk_frag.h"
#include "kk_vert.h"

#define MAX_IMAGES 8

typedef struct {
    float view_proj[16];
    float a[4]; /* Kajiya-Kay: eye; flat: colour */
    float b[4]; /* Kajiya-Kay: light; flat: x = point size */
} Push;

typedef struct {
    Host h;
    VkSurfaceKHR surface;
    WetHairVulkanRequirements *req;
    WetHairVulkanDevice desc;     /* the device as wethair reads it */
    VkDeviceCreateInfo dci;       /* what the device was created with (wethair checks it) */
    VkPhysicalDeviceFeatures2 f2; /* wethair's chain with wide lines and large points added */
    const char *dev_exts[32];
    int wide_lines, large_points;
    int software; /* the device is a CPU implementation (lavapipe, SwiftShader) */
    float line_range[2];
    VkSampleCountFlagBits samples;
    /* Swapchain and what depends on its size */
    VkSwapchainKHR swapchain;
    VkSurfaceFormatKHR format;
    VkExtent2D extent;
    uint32_t image_count;
    VkImage images[MAX_IMAGES];
    VkImageView views[MAX_IMAGES];
    VkFramebuffer framebuffers[MAX_IMAGES];
    VkSemaphore render_done[MAX_IMAGES];
    Image color_ms, depth;
    int can_copy; /* swapchain images allow transfer-source use (screenshots) */
    /* Fixed objects */
    VkRenderPass pass;
    VkPipelineLayout layout;
    VkPipeline hair, water, overlay;
    VkCommandPool pool;
    VkCommandBuffer cmd;
    VkFence fence;
    VkSemaphore acquired;
    /* Buffers */
    HostBuffer index, copy_verts, water_buf, text_buf, pixels;
    uint32_t index_count;
    size_t text_floats;
    float *text;
    size_t text_cap;
    /* The simulation's frames */
    int shared;            /* the simulation lives on this device: draw from its VkBuffer */
    uint64_t last_release; /* the release value signalled last (each is signalled once) */
} Vk;

/* Vulkan clip space from OpenGL's: y down, depth 0..1. */
static void to_vulkan_clip(float m[16]) {
    for (int c = 0; c < 4; c++) {
        m[4 * c + 1] = -m[4 * c + 1];
        m[4 * c + 2] = 0.5f * (m[4 * c + 2] + m[4 * c + 3]);
    }
}

static void destroy_swapchain_objects(Vk *k) {
    VkDevice d = k->h.device;
    for (uint32_t i = 0; i < k->image_count; i++) {
        vkDestroyFramebuffer(d, k->framebuffers[i], NULL);
        vkDestroyImageView(d, k->views[i], NULL);
        vkDestroySemaphore(d, k->render_done[i], NULL);
    }
    k->image_count = 0;
    image_free(&k->h, &k->color_ms);
    image_free(&k->h, &k->depth);
}

/* (Re)creates the swapchain at the window's framebuffer size, with its views, the MSAA and
 * depth images and the framebuffers. */
static void create_swapchain(Viewer *v, Vk *k) {
    VkDevice d = k->h.device;
    vkc_queue_lock(&vkc_queue_mutex); /* wethair's queue is this device's too */
    vkDeviceWaitIdle(d);
    vkc_queue_unlock(&vkc_queue_mutex);
    destroy_swapchain_objects(k);
    VkSurfaceCapabilitiesKHR caps;
    vk_check(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(k->h.phys, k->surface, &caps), "surface capabilities");
    int fw, fh;
    glfwGetFramebufferSize(v->window, &fw, &fh);
    while (fw == 0 || fh == 0) { /* minimised: wait until it has a size again */
        glfwWaitEvents();
        glfwGetFramebufferSize(v->window, &fw, &fh);
    }
    VkExtent2D e = caps.currentExtent;
    if (e.width == UINT32_MAX) {
        e.width = (uint32_t)fw;
        e.height = (uint32_t)fh;
    }
    if (e.width < caps.minImageExtent.width) e.width = caps.minImageExtent.width;
    if (e.height < caps.minImageExtent.height) e.height = caps.minImageExtent.height;
    if (e.width > caps.maxImageExtent.width) e.width = caps.maxImageExtent.width;
    if (e.height > caps.maxImageExtent.height) e.height = caps.maxImageExtent.height;
    k->extent = e;
    v->width = (int)e.width;
    v->height = (int)e.height;
    /* No vsync wait in scripted runs (their frame figures are the work, not the display). */
    VkPresentModeKHR modes[8], mode = VK_PRESENT_MODE_FIFO_KHR;
    uint32_t nm = 8;
    vkGetPhysicalDeviceSurfacePresentModesKHR(k->h.phys, k->surface, &nm, modes);
    for (uint32_t i = 0; i < nm && v->scripted; i++)
        if (modes[i] == VK_PRESENT_MODE_IMMEDIATE_KHR || modes[i] == VK_PRESENT_MODE_MAILBOX_KHR) mode = modes[i];
    k->can_copy = (caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_SRC_BIT) != 0;
    VkSwapchainCreateInfoKHR sci = {.sType = VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
    sci.surface = k->surface;
    sci.minImageCount = caps.minImageCount + 1;
    if (caps.maxImageCount && sci.minImageCount > caps.maxImageCount) sci.minImageCount = caps.maxImageCount;
    sci.imageFormat = k->format.format;
    sci.imageColorSpace = k->format.colorSpace;
    sci.imageExtent = e;
    sci.imageArrayLayers = 1;
    sci.imageUsage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | (k->can_copy ? VK_IMAGE_USAGE_TRANSFER_SRC_BIT : 0);
    sci.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
    sci.preTransform = caps.currentTransform;
    sci.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
    if (!(caps.supportedCompositeAlpha & sci.compositeAlpha)) sci.compositeAlpha = VK_COMPOSITE_ALPHA_INHERIT_BIT_KHR;
    sci.presentMode = mode;
    sci.clipped = VK_TRUE;
    sci.oldSwapchain = k->swapchain;
    VkSwapchainKHR sc;
    vk_check(vkCreateSwapchainKHR(d, &sci, NULL, &sc), "vkCreateSwapchainKHR");
    if (k->swapchain) vkDestroySwapchainKHR(d, k->swapchain, NULL);
    k->swapchain = sc;
    uint32_t n = 0;
    vk_check(vkGetSwapchainImagesKHR(d, sc, &n, NULL), "vkGetSwapchainImagesKHR");
    if (n > MAX_IMAGES) { /* acquire could hand out an index past our arrays */
        fprintf(stderr, "viewer: the swapchain has %u images, at most %d handled\n", n, MAX_IMAGES);
        exit(1);
    }
    vk_check(vkGetSwapchainImagesKHR(d, sc, &n, k->images), "vkGetSwapchainImagesKHR");
    if (k->samples != VK_SAMPLE_COUNT_1_BIT)
        k->color_ms = image(&k->h, e.width, e.height, k->samples, k->format.format,
                            VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSIENT_ATTACHMENT_BIT,
                            VK_IMAGE_ASPECT_COLOR_BIT);
    k->depth = image(&k->h, e.width, e.height, k->samples, VK_FORMAT_D32_SFLOAT,
                     VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, VK_IMAGE_ASPECT_DEPTH_BIT);
    VkSemaphoreCreateInfo sem = {.sType = VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    for (uint32_t i = 0; i < n; i++) {
        VkImageViewCreateInfo vi = {.sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        vi.image = k->images[i];
        vi.viewType = VK_IMAGE_VIEW_TYPE_2D;
        vi.format = k->format.format;
        vi.subresourceRange.aspectMask = VK_IMAGE_ASPECT_COLOR_BIT;
        vi.subresourceRange.levelCount = 1;
        vi.subresourceRange.layerCount = 1;
        vk_check(vkCreateImageView(d, &vi, NULL, &k->views[i]), "vkCreateImageView");
        VkImageView att[3];
        uint32_t na = 0;
        if (k->samples != VK_SAMPLE_COUNT_1_BIT) {
            att[na++] = k->color_ms.view;
            att[na++] = k->depth.view;
            att[na++] = k->views[i];
        } else {
            att[na++] = k->views[i];
            att[na++] = k->depth.view;
        }
        VkFramebufferCreateInfo fbi = {.sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
        fbi.renderPass = k->pass;
        fbi.attachmentCount = na;
        fbi.pAttachments = att;
        fbi.width = e.width;
        fbi.height = e.height;
        fbi.layers = 1;
        vk_check(vkCreateFramebuffer(d, &fbi, NULL, &k->framebuffers[i]), "vkCreateFramebuffer");
        vk_check(vkCreateSemaphore(d, &sem, NULL, &k->render_done[i]), "vkCreateSemaphore");
    }
    k->image_count = n;
}

/* Colour (multisampled and resolved into the swapchain image when samples > 1) and depth. */
static void create_render_pass(Vk *k) {
    int ms = k->samples != VK_SAMPLE_COUNT_1_BIT;
    VkAttachmentDescription att[3] = {{0}, {0}, {0}};
    att[0].format = k->format.format;
    att[0].samples = k->samples;
    att[0].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    att[0].storeOp = ms ? VK_ATTACHMENT_STORE_OP_DONT_CARE : VK_ATTACHMENT_STORE_OP_STORE;
    att[0].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    att[0].stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    att[0].initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    att[0].finalLayout = ms ? VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL : VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
    att[1] = att[0];
    att[1].format = VK_FORMAT_D32_SFLOAT;
    att[1].storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    att[1].finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
    att[2] = att[0];
    att[2].samples = VK_SAMPLE_COUNT_1_BIT;
    att[2].loadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    att[2].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    att[2].finalLayout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
    VkAttachmentReference cref = {0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkAttachmentReference dref = {1, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    VkAttachmentReference rref = {2, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkSubpassDescription sub = {0};
    sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    sub.colorAttachmentCount = 1;
    sub.pColorAttachments = &cref;
    sub.pResolveAttachments = ms ? &rref : NULL;
    sub.pDepthStencilAttachment = &dref;
    /* The swapchain image is written once the acquire has signalled (the submit waits for it
     * at colour output), and the shared depth image once the previous frame's tests are done. */
    VkSubpassDependency dep = {0};
    dep.srcSubpass = VK_SUBPASS_EXTERNAL;
    dep.dstSubpass = 0;
    dep.srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
    dep.dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT;
    dep.srcAccessMask = VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    dep.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    VkRenderPassCreateInfo rpi = {.sType = VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    rpi.attachmentCount = ms ? 3 : 2;
    rpi.pAttachments = att;
    rpi.subpassCount = 1;
    rpi.pSubpasses = &sub;
    rpi.dependencyCount = 1;
    rpi.pDependencies = &dep;
    vk_check(vkCreateRenderPass(k->h.device, &rpi, NULL, &k->pass), "vkCreateRenderPass");
}

/* The three pipelines; the hair's vertex input follows wethair's layout. */
static void create_pipelines(Viewer *v, Vk *k) {
    VkPushConstantRange pcr = {VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(Push)};
    VkPipelineLayoutCreateInfo pli = {.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    pli.pushConstantRangeCount = 1;
    pli.pPushConstantRanges = &pcr;
    vk_check(vkCreatePipelineLayout(k->h.device, &pli, NULL, &k->layout), "vkCreatePipelineLayout");
    VkShaderModule kv = shader_module(&k->h, kk_vert, sizeof kk_vert), kf = shader_module(&k->h, kk_frag, sizeof kk_frag);
    VkShaderModule fv = shader_module(&k->h, flat_vert, sizeof flat_vert);
    VkShaderModule ff = shader_module(&k->h, flat_frag, sizeof flat_frag);
    const WetHairVertexLayout *l = &v->lay;
    VkVertexInputAttributeDescription hair_attrs[3] = {
        {0, 0, VK_FORMAT_R32G32B32_SFLOAT, (uint32_t)l->position_offset},
        {1, 0, VK_FORMAT_R32G32B32_SFLOAT, (uint32_t)l->tangent_offset},
        {2, 0, VK_FORMAT_R32_SFLOAT, (uint32_t)l->wetness_offset},
    };
    VkVertexInputAttributeDescription water_attr = {0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0};
    VkVertexInputAttributeDescription text_attr = {0, 0, VK_FORMAT_R32G32_SFLOAT, 0};
    PipelineDesc hair = {kv, kf, VK_PRIMITIVE_TOPOLOGY_LINE_LIST, l->stride_floats * 4, hair_attrs, 3, 1, k->wide_lines};
    PipelineDesc water = {fv, ff, VK_PRIMITIVE_TOPOLOGY_POINT_LIST, 16, &water_attr, 1, 1, 0};
    PipelineDesc text = {fv, ff, VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST, 8, &text_attr, 1, 0, 0};
    k->hair = pipeline(&k->h, k->pass, k->layout, k->samples, &hair);
    k->water = pipeline(&k->h, k->pass, k->layout, k->samples, &water);
    k->overlay = pipeline(&k->h, k->pass, k->layout, k->samples, &text);
    vkDestroyShaderModule(k->h.device, kv, NULL);
    vkDestroyShaderModule(k->h.device, kf, NULL);
    vkDestroyShaderModule(k->h.device, fv, NULL);
    vkDestroyShaderModule(k->h.device, ff, NULL);
}

static WetHairResult vk_create_sim(Viewer *v, WetHairSimDesc *desc, WetHairSim **out) {
    Vk *k = v->rs;
    k->last_release = 0; /* a new simulation's semaphores count from the start */
    if (desc->backend == WETHAIR_BACKEND_AUTO && k->software) {
        /* As the library's AUTO does: software compute is slower than the CPU backend. */
        printf("viewer: AUTO chose the CPU backend: the Vulkan device is a software implementation "
               "(--backend gpu puts the simulation on it and draws from the shared buffer)\n");
        desc->backend = WETHAIR_BACKEND_CPU;
    }
    if (desc->backend == WETHAIR_BACKEND_CPU) {
        k->shared = 0;
        return wethair_sim_create(desc, out);
    }
    desc->backend = WETHAIR_BACKEND_GPU;
    WetHairResult r = wethair_sim_create_vulkan(desc, &k->desc, out);
    k->shared = r == WETHAIR_OK;
    return r;
}

static const char *vk_source(const Viewer *v) {
    const Vk *k = v->rs;
    return k->shared ? "shared VkBuffer" : "copy path";
}

/* Records the frame: strands, water, overlay (its shadow first); the copy for a screenshot. */
/* Where this frame's strands and water come from: wethair's buffers or ours. */
typedef struct {
    VkBuffer verts;
    VkDeviceSize verts_offset;
    VkBuffer water, water_draw; /* water_draw: an indirect draw's command (shared), else NULL */
    VkDeviceSize water_offset, water_draw_offset;
    uint32_t water_count; /* the copy path's count */
} Sources;

static void record(Viewer *v, Vk *k, uint32_t img, const Sources *src, int screenshot) {
    VkCommandBuffer cmd = k->cmd;
    vk_check(vkResetCommandBuffer(cmd, 0), "vkResetCommandBuffer");
    VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    vk_check(vkBeginCommandBuffer(cmd, &bi), "vkBeginCommandBuffer");
    VkClearValue clear[3];
    memset(clear, 0, sizeof clear);
    for (int c = 0; c < 3; c++) clear[0].color.float32[c] = VIEWER_CLEAR[c];
    clear[0].color.float32[3] = 1.0f;
    clear[1].depthStencil.depth = 1.0f;
    VkRenderPassBeginInfo rbi = {.sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    rbi.renderPass = k->pass;
    rbi.framebuffer = k->framebuffers[img];
    rbi.renderArea.extent = k->extent;
    rbi.clearValueCount = 2;
    rbi.pClearValues = clear;
    vkCmdBeginRenderPass(cmd, &rbi, VK_SUBPASS_CONTENTS_INLINE);
    VkViewport vp = {0, 0, (float)k->extent.width, (float)k->extent.height, 0, 1};
    VkRect2D sc = {{0, 0}, k->extent};
    vkCmdSetViewport(cmd, 0, 1, &vp);
    vkCmdSetScissor(cmd, 0, 1, &sc);
    const VkShaderStageFlags stages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
    Push pc;
    memset(&pc, 0, sizeof pc);
    float eye[3];
    viewer_view_proj(v, pc.view_proj, eye);
    to_vulkan_clip(pc.view_proj);
    float ll = sqrtf(VIEWER_LIGHT[0] * VIEWER_LIGHT[0] + VIEWER_LIGHT[1] * VIEWER_LIGHT[1] + VIEWER_LIGHT[2] * VIEWER_LIGHT[2]);
    for (int c = 0; c < 3; c++) {
        pc.a[c] = eye[c];
        pc.b[c] = VIEWER_LIGHT[c] / ll;
    }
    pc.a[3] = 1.0f;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, k->hair);
    if (k->wide_lines) {
        float w = v->line_width;
        w = w < k->line_range[0] ? k->line_range[0] : w > k->line_range[1] ? k->line_range[1] : w;
        vkCmdSetLineWidth(cmd, w);
    }
    vkCmdPushConstants(cmd, k->layout, stages, 0, sizeof pc, &pc);
    vkCmdBindVertexBuffers(cmd, 0, 1, &src->verts, &src->verts_offset);
    vkCmdBindIndexBuffer(cmd, k->index.buf, 0, VK_INDEX_TYPE_UINT32);
    vkCmdDrawIndexed(cmd, k->index_count, 1, 0, 0, 0);
    VkDeviceSize zero = 0;
    if (src->water_draw || src->water_count) {
        for (int c = 0; c < 3; c++) pc.a[c] = VIEWER_WATER[c];
        pc.b[0] = k->large_points ? VIEWER_WATER_POINT : 1.0f;
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, k->water);
        vkCmdPushConstants(cmd, k->layout, stages, 0, sizeof pc, &pc);
        vkCmdBindVertexBuffers(cmd, 0, 1, &src->water, &src->water_offset);
        if (src->water_draw) vkCmdDrawIndirect(cmd, src->water_draw, src->water_draw_offset, 1, 0);
        else vkCmdDraw(cmd, src->water_count, 1, 0, 0);
    }
    if (k->text_floats) {
        /* Overlay coordinates are y up: flip into Vulkan's clip space; the shadow is shifted. */
        memset(&pc, 0, sizeof pc);
        float s = (float)viewer_text_scale(v);
        pc.view_proj[0] = 1.0f;
        pc.view_proj[5] = -1.0f;
        pc.view_proj[10] = 1.0f;
        pc.view_proj[15] = 1.0f;
        pc.view_proj[12] = 2.0f * s / (float)k->extent.width;
        pc.view_proj[13] = 2.0f * s / (float)k->extent.height;
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, k->overlay);
        vkCmdBindVertexBuffers(cmd, 0, 1, &k->text_buf.buf, &zero);
        vkCmdPushConstants(cmd, k->layout, stages, 0, sizeof pc, &pc);
        vkCmdDraw(cmd, (uint32_t)(k->text_floats / 2), 1, 0, 0);
        pc.view_proj[12] = pc.view_proj[13] = 0.0f;
        pc.a[0] = 0.95f;
        pc.a[1] = 0.95f;
        pc.a[2] = 0.85f;
        vkCmdPushConstants(cmd, k->layout, stages, 0, sizeof pc, &pc);
        vkCmdDraw(cmd, (uint32_t)(k->text_floats / 2), 1, 0, 0);
    }
    vkCmdEndRenderPass(cmd);
    if (screenshot) {
        VkImageMemoryBarrier ib = {.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
        ib.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
        ib.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
        ib.oldLayout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
        ib.newLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
        ib.srcQueueFamilyIndex = ib.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        ib.image = k->images[img];
        ib.subresourceRange.aspectMask = VK_IMAGE_ASPECT_COLOR_BIT;
        ib.subresourceRange.levelCount = 1;
        ib.subresourceRange.layerCount = 1;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0,
                             NULL, 0, NULL, 1, &ib);
        VkBufferImageCopy bic = {0};
        bic.imageSubresource.aspectMask = VK_IMAGE_ASPECT_COLOR_BIT;
        bic.imageSubresource.layerCount = 1;
        bic.imageExtent.width = k->extent.width;
        bic.imageExtent.height = k->extent.height;
        bic.imageExtent.depth = 1;
        vkCmdCopyImageToBuffer(cmd, k->images[img], VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, k->pixels.buf, 1, &bic);
        ib.srcAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
        ib.dstAccessMask = 0;
        ib.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
        ib.newLayout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, 0, 0, NULL, 0,
                             NULL, 1, &ib);
        VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        mb.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        mb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &mb, 0, NULL, 0, NULL);
    }
    vk_check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
}

/* The screenshot's pixels (BGRA or RGBA in the swapchain's format) as RGB rows. */
static void read_pixels(const Vk *k, uint8_t *rgb) {
    const uint8_t *px = k->pixels.map;
    int bgr = k->format.format == VK_FORMAT_B8G8R8A8_UNORM || k->format.format == VK_FORMAT_B8G8R8A8_SRGB;
    size_t n = (size_t)k->extent.width * k->extent.height;
    for (size_t i = 0; i < n; i++) {
        rgb[3 * i + 0] = px[4 * i + (bgr ? 2 : 0)];
        rgb[3 * i + 1] = px[4 * i + 1];
        rgb[3 * i + 2] = px[4 * i + (bgr ? 0 : 2)];
    }
}

static void vk_draw(Viewer *v, uint8_t *rgb) {
    Vk *k = v->rs;
    VkDevice d = k->h.device;
    if (!k->index.buf) {
        uint32_t n = 0, *ix = viewer_line_indices(&v->lay, &n);
        k->index = host_buffer(&k->h, (VkDeviceSize)n * sizeof(uint32_t), VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
        memcpy(k->index.map, ix, (size_t)n * sizeof(uint32_t));
        k->index_count = n;
        free(ix);
        k->water_buf = host_buffer(&k->h, sizeof(float) * 4 * MAX_PARTICLES, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
        create_pipelines(v, k);
    }
    uint32_t img = 0;
    VkResult r;
    while ((r = vkAcquireNextImageKHR(d, k->swapchain, UINT64_MAX, k->acquired, VK_NULL_HANDLE, &img)) ==
           VK_ERROR_OUT_OF_DATE_KHR)
        create_swapchain(v, k);
    if (r != VK_SUBOPTIMAL_KHR) vk_check(r, "vkAcquireNextImageKHR");
    int resize = r == VK_SUBOPTIMAL_KHR;
    int screenshot = rgb && k->can_copy;
    if (rgb && !k->can_copy) fprintf(stderr, "viewer: this swapchain cannot be copied from; the screenshot is black\n");
    size_t pixel_bytes = (size_t)k->extent.width * k->extent.height * 4;
    if (screenshot && (!k->pixels.buf || pixel_bytes > k->pixels.size)) {
        host_buffer_free(&k->h, &k->pixels);
        k->pixels = host_buffer(&k->h, pixel_bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT);
    }

    /* The strands and the water: wethair's own VkBuffers, or the copy path into ours. */
    Sources src;
    memset(&src, 0, sizeof src);
    WetHairVulkanBuffer vb;
    memset(&vb, 0, sizeof vb);
    vb.struct_size = sizeof vb;
    int sync = 0;
    if (k->shared) {
        wh_check(wethair_sim_get_vulkan_buffer(v->sim, &vb), "wethair_sim_get_vulkan_buffer");
        WetHairVulkanWater w;
        memset(&w, 0, sizeof w);
        w.struct_size = sizeof w;
        wh_check(wethair_sim_get_vulkan_water(v->sim, &w), "wethair_sim_get_vulkan_water");
        src.verts = (VkBuffer)(uintptr_t)vb.buffer;
        src.verts_offset = vb.offset;
        src.water = (VkBuffer)(uintptr_t)w.buffer;
        src.water_offset = w.offset;
        src.water_draw = (VkBuffer)(uintptr_t)w.draw_buffer;
        src.water_draw_offset = w.draw_offset;
        sync = vb.release_value > k->last_release; /* a paused host is handed the same frame again */
    } else {
        size_t cap = (size_t)v->lay.vertex_count * v->lay.stride_floats, written = 0;
        if (!k->copy_verts.buf) k->copy_verts = host_buffer(&k->h, cap * sizeof(float), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
        wh_check(wethair_sim_get_vertex_buffer(v->sim, k->copy_verts.map, cap, &written), "wethair_sim_get_vertex_buffer");
        src.verts = k->copy_verts.buf;
        /* Packed xyz from the copy path, spread to the shared layout's vec4 in place (backwards). */
        float *wv = k->water_buf.map;
        wh_check(wethair_sim_get_water(v->sim, wv, MAX_PARTICLES, &src.water_count), "wethair_sim_get_water");
        for (uint32_t i = src.water_count; i-- > 0;) {
            float x = wv[3 * i], y = wv[3 * i + 1], z = wv[3 * i + 2];
            wv[4 * i] = x;
            wv[4 * i + 1] = y;
            wv[4 * i + 2] = z;
            wv[4 * i + 3] = 1.0f;
        }
        src.water = k->water_buf.buf;
    }
    k->text_floats = viewer_text_triangles(v, &k->text, &k->text_cap);
    if (k->text_floats * sizeof(float) > k->text_buf.size) {
        host_buffer_free(&k->h, &k->text_buf);
        k->text_buf = host_buffer(&k->h, k->text_floats * sizeof(float), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
    }
    if (k->text_floats) memcpy(k->text_buf.map, k->text, k->text_floats * sizeof(float));
    record(v, k, img, &src, screenshot);

    /* Wait for the swapchain image and wethair's write; signal our draw's end and the release. */
    VkSemaphore waits[2] = {k->acquired, (VkSemaphore)(uintptr_t)vb.ready_semaphore};
    VkSemaphore signals[2] = {k->render_done[img], (VkSemaphore)(uintptr_t)vb.release_semaphore};
    VkPipelineStageFlags stages[2] = {VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                                      VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_VERTEX_INPUT_BIT};
    uint64_t wait_values[2] = {0, vb.ready_value}, signal_values[2] = {0, vb.release_value};
    VkTimelineSemaphoreSubmitInfo tsi = {.sType = VK_STRUCTURE_TYPE_TIMELINE_SEMAPHORE_SUBMIT_INFO};
    tsi.waitSemaphoreValueCount = sync ? 2 : 1;
    tsi.pWaitSemaphoreValues = wait_values;
    tsi.signalSemaphoreValueCount = sync ? 2 : 1;
    tsi.pSignalSemaphoreValues = signal_values;
    VkSubmitInfo si = {.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.pNext = &tsi;
    si.waitSemaphoreCount = sync ? 2 : 1;
    si.pWaitSemaphores = waits;
    si.pWaitDstStageMask = stages;
    si.commandBufferCount = 1;
    si.pCommandBuffers = &k->cmd;
    si.signalSemaphoreCount = sync ? 2 : 1;
    si.pSignalSemaphores = signals;
    vk_check(locked_submit(&k->h, &si, k->fence), "vkQueueSubmit");
    if (sync) k->last_release = vb.release_value;
    VkPresentInfoKHR pi = {.sType = VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    pi.waitSemaphoreCount = 1;
    pi.pWaitSemaphores = &k->render_done[img];
    pi.swapchainCount = 1;
    pi.pSwapchains = &k->swapchain;
    pi.pImageIndices = &img;
    vkc_queue_lock(&vkc_queue_mutex);
    r = vkQueuePresentKHR(k->h.queue, &pi);
    vkc_queue_unlock(&vkc_queue_mutex);
    if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR) resize = 1;
    else vk_check(r, "vkQueuePresentKHR");
    vk_check(vkWaitForFences(d, 1, &k->fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
    vk_check(vkResetFences(d, 1, &k->fence), "vkResetFences");
    if (screenshot) read_pixels(k, rgb);
    else if (rgb) memset(rgb, 0, (size_t)v->width * v->height * 3);
    int fw, fh;
    glfwGetFramebufferSize(v->window, &fw, &fh);
    if (resize || (uint32_t)fw != k->extent.width || (uint32_t)fh != k->extent.height) create_swapchain(v, k);
}

/* Destroys whatever exists (also after a failed open). */
static void vk_teardown(Vk *k) {
    VkDevice d = k->h.device;
    if (d) {
        vkDeviceWaitIdle(d);
        destroy_swapchain_objects(k);
        if (k->swapchain) vkDestroySwapchainKHR(d, k->swapchain, NULL);
        HostBuffer *bufs[] = {&k->index, &k->copy_verts, &k->water_buf, &k->text_buf, &k->pixels};
        for (size_t i = 0; i < sizeof bufs / sizeof bufs[0]; i++) host_buffer_free(&k->h, bufs[i]);
        VkPipeline pipes[] = {k->hair, k->water, k->overlay};
        for (int i = 0; i < 3; i++)
            if (pipes[i]) vkDestroyPipeline(d, pipes[i], NULL);
        if (k->layout) vkDestroyPipelineLayout(d, k->layout, NULL);
        if (k->pass) vkDestroyRenderPass(d, k->pass, NULL);
        if (k->fence) vkDestroyFence(d, k->fence, NULL);
        if (k->acquired) vkDestroySemaphore(d, k->acquired, NULL);
        if (k->pool) vkDestroyCommandPool(d, k->pool, NULL);
        vkDestroyDevice(d, NULL);
    }
    if (k->req) wethair_vulkan_requirements_destroy(k->req);
    if (k->surface) vkDestroySurfaceKHR(k->h.instance, k->surface, NULL);
    destroy_instance(&k->h);
    free(k->text);
    free(k);
}

static void vk_close(Viewer *v) {
    vk_teardown(v->rs);
    v->rs = NULL;
    glfwDestroyWindow(v->window);
    v->window = NULL;
    if (v->validate) {
        printf("viewer: validation: %d errors\n", vkc_validation_errors);
        if (vkc_validation_errors) exit(1);
    }
}

/* A queue family that draws, computes (wethair's passes) and presents to the window. */
static int pick_queue_family(VkInstance inst, VkPhysicalDevice p, uint32_t *family) {
    VkQueueFamilyProperties q[16];
    uint32_t n = 16;
    vkGetPhysicalDeviceQueueFamilyProperties(p, &n, q);
    const VkQueueFlags want = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
    for (uint32_t i = 0; i < n; i++)
        if ((q[i].queueFlags & want) == want && glfwGetPhysicalDevicePresentationSupport(inst, p, i)) {
            *family = i;
            return 1;
        }
    return 0;
}

/* The first device (discrete GPUs first) that presents, has a swapchain and meets wethair's
 * requirements; their chain and extensions are kept in `k`. */
static int pick_device(Vk *k, char *why, size_t why_len) {
    VkPhysicalDevice devs[8];
    uint32_t n = 8;
    VkResult r = vkEnumeratePhysicalDevices(k->h.instance, &n, devs);
    if ((r != VK_SUCCESS && r != VK_INCOMPLETE) || n == 0) {
        snprintf(why, why_len, "no Vulkan physical device");
        return 0;
    }
    snprintf(why, why_len, "no device presents to this window");
    for (int pass = 0; pass < 2; pass++)
        for (uint32_t i = 0; i < n; i++) {
            VkPhysicalDeviceProperties props;
            vkGetPhysicalDeviceProperties(devs[i], &props);
            if ((props.deviceType == VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU) != (pass == 0)) continue;
            if (!pick_queue_family(k->h.instance, devs[i], &k->h.queue_family)) continue;
            k->h.phys = devs[i];
            WetHairVulkanDevice d = describe(&k->h);
            if (wethair_vulkan_requirements_create(&d, &k->req) != WETHAIR_OK) {
                snprintf(why, why_len, "%s: %s", props.deviceName, wethair_last_error_message());
                continue;
            }
            return 1;
        }
    return 0;
}

/* The device: wethair's extensions and feature chain plus the swapchain, wide lines and
 * large points where the device has them. */
static int create_device(Vk *k, char *why, size_t why_len) {
    WetHairVulkanRequirementsInfo info;
    memset(&info, 0, sizeof info);
    info.struct_size = sizeof info;
    wh_check(wethair_vulkan_requirements_get_info(k->req, &info), "wethair_vulkan_requirements_get_info");
    uint32_t ne = 0;
    for (uint32_t i = 0; i < info.device_extension_count && ne < 31; i++) k->dev_exts[ne++] = info.device_extensions[i];
    k->dev_exts[ne++] = VK_KHR_SWAPCHAIN_EXTENSION_NAME;
    VkPhysicalDeviceFeatures have;
    vkGetPhysicalDeviceFeatures(k->h.phys, &have);
    k->f2 = *(const VkPhysicalDeviceFeatures2 *)info.features; /* pNext still points at wethair's chain */
    k->wide_lines = have.wideLines;
    k->large_points = have.largePoints;
    k->f2.features.wideLines = have.wideLines;
    k->f2.features.largePoints = have.largePoints;
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(k->h.phys, &props);
    k->software = props.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
    k->line_range[0] = props.limits.lineWidthRange[0];
    k->line_range[1] = props.limits.lineWidthRange[1];
    static float priority = 1.0f;
    static VkDeviceQueueCreateInfo qi = {.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qi.queueFamilyIndex = k->h.queue_family;
    qi.queueCount = 1;
    qi.pQueuePriorities = &priority;
    VkDeviceCreateInfo ci = {.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    ci.pNext = &k->f2;
    ci.queueCreateInfoCount = 1;
    ci.pQueueCreateInfos = &qi;
    ci.enabledExtensionCount = ne;
    ci.ppEnabledExtensionNames = k->dev_exts;
    VkResult r = vkCreateDevice(k->h.phys, &ci, NULL, &k->h.device);
    if (r != VK_SUCCESS) {
        snprintf(why, why_len, "vkCreateDevice failed: VkResult %d", (int)r);
        return 0;
    }
    k->dci = ci;
    vkGetDeviceQueue(k->h.device, k->h.queue_family, 0, &k->h.queue);
    vkGetPhysicalDeviceMemoryProperties(k->h.phys, &k->h.mem);
    k->desc = describe(&k->h);
    k->desc.device = k->h.device;
    k->desc.device_extension_count = ne;
    k->desc.device_extensions = k->dev_exts;
    k->desc.enabled_features = &k->dci;
    return 1;
}

int vk_renderer_open(Viewer *v, char *why, size_t why_len) {
    if (!glfwVulkanSupported()) {
        snprintf(why, why_len, "GLFW finds no Vulkan loader with surface support");
        return 0;
    }
    uint32_t n_surface = 0;
    const char **surface_exts = glfwGetRequiredInstanceExtensions(&n_surface);
    Vk *k = calloc(1, sizeof *k);
    if (!k) exit(1);
    if (!create_instance(&k->h, v->validate, surface_exts, n_surface, why, why_len) || !pick_device(k, why, why_len) ||
        !create_device(k, why, why_len)) {
        vk_teardown(k);
        return 0;
    }
    glfwDefaultWindowHints();
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    v->window = glfwCreateWindow(v->width, v->height, "wethair", NULL, NULL);
    VkResult r = v->window ? glfwCreateWindowSurface(k->h.instance, v->window, NULL, &k->surface) : VK_ERROR_INITIALIZATION_FAILED;
    VkBool32 presents = VK_FALSE;
    if (r == VK_SUCCESS)
        vkGetPhysicalDeviceSurfaceSupportKHR(k->h.phys, k->h.queue_family, k->surface, &presents);
    if (r != VK_SUCCESS || !presents) {
        snprintf(why, why_len, "no Vulkan surface for the window (VkResult %d)", (int)r);
        vk_teardown(k);
        if (v->window) glfwDestroyWindow(v->window);
        v->window = NULL;
        return 0;
    }
    /* A UNORM format: the Kajiya-Kay shader gamma-encodes itself. */
    VkSurfaceFormatKHR formats[32];
    uint32_t nf = 32;
    vkGetPhysicalDeviceSurfaceFormatsKHR(k->h.phys, k->surface, &nf, formats);
    k->format = formats[0];
    for (uint32_t i = 0; i < nf; i++)
        if ((formats[i].format == VK_FORMAT_B8G8R8A8_UNORM || formats[i].format == VK_FORMAT_R8G8B8A8_UNORM) &&
            formats[i].colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR) {
            k->format = formats[i];
            break;
        }
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(k->h.phys, &props);
    VkSampleCountFlags counts = props.limits.framebufferColorSampleCounts & props.limits.framebufferDepthSampleCounts;
    k->samples = v->samples >= 4 && (counts & VK_SAMPLE_COUNT_4_BIT) ? VK_SAMPLE_COUNT_4_BIT : VK_SAMPLE_COUNT_1_BIT;
    v->samples = (int)k->samples;
    create_render_pass(k);
    VkCommandPoolCreateInfo cpi = {.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    cpi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    cpi.queueFamilyIndex = k->h.queue_family;
    vk_check(vkCreateCommandPool(k->h.device, &cpi, NULL, &k->pool), "vkCreateCommandPool");
    VkCommandBufferAllocateInfo cai = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    cai.commandPool = k->pool;
    cai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    cai.commandBufferCount = 1;
    vk_check(vkAllocateCommandBuffers(k->h.device, &cai, &k->cmd), "vkAllocateCommandBuffers");
    VkFenceCreateInfo fci = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    vk_check(vkCreateFence(k->h.device, &fci, NULL, &k->fence), "vkCreateFence");
    VkSemaphoreCreateInfo sci = {.sType = VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    vk_check(vkCreateSemaphore(k->h.device, &sci, NULL, &k->acquired), "vkCreateSemaphore");
    v->rs = k;
    v->api = "Vulkan";
    v->r.create_sim = vk_create_sim;
    v->r.draw = vk_draw;
    v->r.source = vk_source;
    v->r.close = vk_close;
    create_swapchain(v, k);
    printf("viewer: drawing with Vulkan %u.%u on %s (%ux%u, %d samples, %s lines) from the shared VkBuffer of GPU "
           "simulations on this device\n",
           VK_API_VERSION_MAJOR(k->h.api_version), VK_API_VERSION_MINOR(k->h.api_version), props.deviceName,
           k->extent.width, k->extent.height, (int)k->samples, k->wide_lines ? "wide" : "1-pixel");
    return 1;
}
