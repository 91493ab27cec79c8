/* Plays Unity's part for the wethair Unity plugin on a real Vulkan device (lavapipe in the
 * tests): hand-built IUnityInterfaces / IUnityGraphics / IUnityGraphicsVulkan tables, the
 * plugin loaded at startup so it intercepts instance and device creation, a "Unity" instance
 * and device created through the intercepted vkGetInstanceProcAddr asking for nothing wethair
 * needs, then simulations made through wethair_unity_sim_create and stepped by the render event.
 *
 * usage: unity_fake [--validate] [--aggregate]
 *   --validate   run under VK_LAYER_KHRONOS_validation; any error fails
 *   --aggregate  "Unity" chains a VkPhysicalDeviceVulkan12Features without timelineSemaphore:
 *                the plugin cannot add it, says so, and simulations fall back to their own device
 * Build: libwethair with cargo feature `unity`. */
#include <vulkan/vulkan.h>

#include "scene.h"

/* The plugin's entry points (Unity's to call; not in wethair.h). */
typedef struct { unsigned long long high, low; } UnityInterfaceGUID;
typedef struct {
    void *(*GetInterface)(UnityInterfaceGUID guid);
    void (*RegisterInterface)(UnityInterfaceGUID guid, void *ptr);
    void *(*GetInterfaceSplit)(unsigned long long high, unsigned long long low);
    void (*RegisterInterfaceSplit)(unsigned long long high, unsigned long long low, void *ptr);
} IUnityInterfaces;
void UnityPluginLoad(IUnityInterfaces *interfaces);
void UnityPluginUnload(void);

typedef void (*DeviceEventCallback)(int event);
typedef struct {
    int (*GetRenderer)(void);
    void (*RegisterDeviceEventCallback)(DeviceEventCallback cb);
    void (*UnregisterDeviceEventCallback)(DeviceEventCallback cb);
    int (*ReserveEventIDRange)(int count);
} IUnityGraphics;
typedef struct {
    VkPipelineCache pipelineCache;
    VkInstance instance;
    VkPhysicalDevice physicalDevice;
    VkDevice device;
    VkQueue graphicsQueue;
    PFN_vkGetInstanceProcAddr getInstanceProcAddr;
    unsigned int queueFamilyIndex;
    void *reserved[8];
} UnityVulkanInstance;
typedef struct {
    int renderPassPrecondition;
    int graphicsQueueAccess;
    uint32_t flags;
} UnityVulkanPluginEventConfig;
typedef PFN_vkGetInstanceProcAddr (*UnityVulkanInitCallback)(PFN_vkGetInstanceProcAddr gipa, void *user);
typedef struct {
    _Bool (*InterceptInitialization)(UnityVulkanInitCallback func, void *user);
    void *InterceptVulkanAPI;
    void (*ConfigureEvent)(int eventId, const UnityVulkanPluginEventConfig *config);
    UnityVulkanInstance (*Instance)(void);
} IUnityGraphicsVulkan;

static DeviceEventCallback device_cb;
static UnityVulkanInitCallback init_cb;
static void *init_user;
static UnityVulkanInstance unity_vk;
static int configured = 0, validation_errors = 0;

static int get_renderer(void) { return 21; /* Vulkan */ }
static void register_cb(DeviceEventCallback cb) { device_cb = cb; }
static void unregister_cb(DeviceEventCallback cb) { if (cb == device_cb) device_cb = NULL; }
static int reserve(int count) { (void)count; return 4000; }
static _Bool intercept(UnityVulkanInitCallback func, void *user) { init_cb = func; init_user = user; return 1; }
static void configure(int id, const UnityVulkanPluginEventConfig *c) { configured = id == 4000 && c->graphicsQueueAccess == 1; }
static UnityVulkanInstance instance_data(void) { return unity_vk; }
static IUnityGraphics graphics = {get_renderer, register_cb, unregister_cb, reserve};
static IUnityGraphicsVulkan vulkan = {intercept, NULL, configure, instance_data};
static void *get_split(unsigned long long high, unsigned long long low) {
    if (high == 0x7CBA0A9CA4DDB544ull && low == 0x8C5AD4926EB17B11ull) return &graphics;
    if (high == 0x95355348d4ef4e11ull && low == 0x9789313dfcffcc87ull) return &vulkan;
    return NULL;
}

static VKAPI_ATTR VkBool32 VKAPI_CALL on_validation(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                    VkDebugUtilsMessageTypeFlagsEXT type,
                                                    const VkDebugUtilsMessengerCallbackDataEXT *data, void *user) {
    (void)type;
    (void)user;
    const char *msg = data->pMessage ? data->pMessage : "";
    if (strstr(msg, "InconsistentSpirv") && strstr(msg, "operand: 10")) return VK_FALSE;
    if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
        fprintf(stderr, "validation error: %s\n", msg);
        validation_errors++;
    }
    return VK_FALSE;
}

static WetHairUnityStatus status(void) {
    WetHairUnityStatus st;
    memset(&st, 0, sizeof st);
    st.struct_size = sizeof st;
    wh_check(wethair_unity_get_status(&st), "wethair_unity_get_status");
    return st;
}

int main(int argc, char **argv) {
    int validate = 0, aggregate = 0, fails = 0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--validate")) validate = 1;
        else if (!strcmp(argv[i], "--aggregate")) aggregate = 1;
        else {
            fprintf(stderr, "usage: %s [--validate] [--aggregate]\n", argv[0]);
            return 2;
        }
    }
    IUnityInterfaces interfaces = {NULL, NULL, get_split, NULL};
    UnityPluginLoad(&interfaces);
    if (!init_cb || !device_cb) {
        fprintf(stderr, "the plugin did not ask to intercept initialization or for device events\n");
        return 1;
    }
    /* Unity starts Vulkan through the plugin's hook: an instance and a device asking for
     * nothing wethair needs (apiVersion 1.0, no extensions), one core feature of its own. */
    PFN_vkGetInstanceProcAddr gipa = init_cb(vkGetInstanceProcAddr, init_user);
    PFN_vkCreateInstance create_instance = (PFN_vkCreateInstance)gipa(NULL, "vkCreateInstance");
    VkApplicationInfo app = {.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO, .apiVersion = VK_API_VERSION_1_0};
    const char *layers[] = {"VK_LAYER_KHRONOS_validation"};
    const char *debug_ext[] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME};
    VkDebugUtilsMessengerCreateInfoEXT mi = {.sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    mi.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    mi.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT;
    mi.pfnUserCallback = on_validation;
    VkInstanceCreateInfo ici = {.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO, .pApplicationInfo = &app};
    if (validate) {
        ici.enabledLayerCount = 1;
        ici.ppEnabledLayerNames = layers;
        ici.enabledExtensionCount = 1;
        ici.ppEnabledExtensionNames = debug_ext;
        ici.pNext = &mi;
    }
    VkInstance instance;
    if (create_instance(&ici, NULL, &instance) != VK_SUCCESS) return fprintf(stderr, "vkCreateInstance failed\n"), 1;
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    if (validate) {
        PFN_vkCreateDebugUtilsMessengerEXT f =
            (PFN_vkCreateDebugUtilsMessengerEXT)gipa(instance, "vkCreateDebugUtilsMessengerEXT");
        if (f) f(instance, &mi, NULL, &messenger);
    }
    uint32_t n = 1;
    VkPhysicalDevice phys;
    PFN_vkEnumeratePhysicalDevices enumerate = (PFN_vkEnumeratePhysicalDevices)gipa(instance, "vkEnumeratePhysicalDevices");
    if (enumerate(instance, &n, &phys) < 0 || n == 0) return fprintf(stderr, "no physical device\n"), 1;
    float prio = 1.0f;
    VkDeviceQueueCreateInfo qi = {.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO, .queueFamilyIndex = 0,
                                  .queueCount = 1, .pQueuePriorities = &prio};
    VkPhysicalDeviceFeatures own = {.samplerAnisotropy = VK_FALSE, .shaderClipDistance = VK_TRUE};
    VkPhysicalDeviceVulkan12Features v12 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkDeviceCreateInfo dci = {.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, .queueCreateInfoCount = 1,
                              .pQueueCreateInfos = &qi, .pEnabledFeatures = &own};
    if (aggregate) dci.pNext = &v12; /* Unity's own 1.2 features, without timelineSemaphore */
    PFN_vkCreateDevice create_device = (PFN_vkCreateDevice)gipa(instance, "vkCreateDevice");
    VkDevice device;
    if (create_device(phys, &dci, NULL, &device) != VK_SUCCESS) return fprintf(stderr, "vkCreateDevice failed\n"), 1;
    PFN_vkGetDeviceQueue get_queue = (PFN_vkGetDeviceQueue)gipa(instance, "vkGetDeviceQueue");
    VkQueue queue;
    get_queue(device, 0, 0, &queue);
    unity_vk.instance = instance;
    unity_vk.physicalDevice = phys;
    unity_vk.device = device;
    unity_vk.graphicsQueue = queue;
    unity_vk.getInstanceProcAddr = vkGetInstanceProcAddr;
    unity_vk.queueFamilyIndex = 0;
    device_cb(0); /* kUnityGfxDeviceEventInitialize */

    WetHairUnityStatus st = status();
    printf("plugin: renderer %d, on Unity's device %u, event base %d%s%s\n", st.renderer, st.on_unity_device,
           st.event_id_base, st.reason[0] ? ": " : "", (const char *)st.reason);
    if (aggregate) {
        if (st.on_unity_device || !strstr((const char *)st.reason, "timelineSemaphore")) {
            fprintf(stderr, "check failed: a missing timelineSemaphore in Unity's 1.2 features must be named\n");
            fails++;
        }
    } else if (!st.on_unity_device || !configured) {
        fprintf(stderr, "check failed: simulations should run on Unity's device, its event configured\n");
        fails++;
    }

    /* A simulation through the Unity entry, stepped by the render event. */
    WetHairGroom *groom = NULL;
    wh_check(wethair_groom_create_paper_scene(2000, 6, &groom), "wethair_groom_create_paper_scene");
    WetHairSimDesc desc;
    wethair_sim_desc_default(&desc);
    desc.groom = groom;
    desc.backend = WETHAIR_BACKEND_GPU;
    WetHairSim *sim = NULL;
    wh_check(wethair_unity_sim_create(&desc, &sim), "wethair_unity_sim_create");
    wethair_groom_destroy(groom);
    wh_print_backend(sim);
    WetHairUnityRenderEvent event = wethair_unity_get_render_event_func();
    WetHairUnityStep step = {sizeof step, 1.0f / 60.0f, sim, 99, 0};
    for (int f = 0; f < 10; f++) {
        event(st.event_id_base, &step);
        if (step.result != WETHAIR_OK) {
            fprintf(stderr, "check failed: render-event step returned %u: %s\n", step.result, wethair_last_error_message());
            fails++;
            break;
        }
    }
    WetHairVulkanBuffer vb;
    memset(&vb, 0, sizeof vb);
    vb.struct_size = sizeof vb;
    WetHairResult r = wethair_sim_get_vulkan_buffer(sim, &vb);
    if (!aggregate) {
        if (r != WETHAIR_OK) {
            fprintf(stderr, "check failed: no shared buffer on Unity's device: %s\n", wethair_last_error_message());
            fails++;
        } else {
            /* Release the frame we did not draw, as the contract asks. */
            VkSemaphoreSignalInfo si = {.sType = VK_STRUCTURE_TYPE_SEMAPHORE_SIGNAL_INFO,
                                        .semaphore = (VkSemaphore)(uintptr_t)vb.release_semaphore,
                                        .value = vb.release_value};
            PFN_vkSignalSemaphore sig = (PFN_vkSignalSemaphore)gipa(instance, "vkSignalSemaphore");
            sig(device, &si);
            printf("shared VkBuffer on Unity's device: %u vertices, stride %u bytes\n", vb.vertex_count, vb.stride_bytes);
        }
    } else if (r != WETHAIR_ERROR_UNSUPPORTED) {
        fprintf(stderr, "check failed: a simulation on its own device has no shared buffer\n");
        fails++;
    }
    WetHairStats stats = wh_stats(sim);
    printf("render-event steps: %llu, %u points\n", (unsigned long long)stats.steps, stats.points);
    if (stats.steps != 10) fails++;
    wethair_sim_destroy(sim);
    device_cb(1); /* kUnityGfxDeviceEventShutdown */
    UnityPluginUnload();
    if (device_cb) {
        fprintf(stderr, "check failed: the device callback is still registered after unload\n");
        fails++;
    }
    /* The plugin is gone, and its hook with it: Unity tears down through the loader. */
    vkDestroyDevice(device, NULL);
    if (messenger) {
        PFN_vkDestroyDebugUtilsMessengerEXT f =
            (PFN_vkDestroyDebugUtilsMessengerEXT)vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT");
        if (f) f(instance, messenger, NULL);
    }
    vkDestroyInstance(instance, NULL);
    if (validate) printf("validation: %d errors\n", validation_errors);
    printf("unity_fake%s: %s\n", aggregate ? " --aggregate" : "", fails || validation_errors ? "FAILED" : "OK");
    return fails || validation_errors ? 1 : 0;
}
