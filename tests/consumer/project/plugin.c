/* A plugin built against the installed plugin header alone: it must stand on its own, without
 * statfilter.h and without linking libstatfilter. */
#include <statfilter/statfilter_plugin.h>

static sf_status create(void** instance, char* error, size_t size) {
    static int state;
    (void)error;
    (void)size;
    *instance = &state;
    return SF_OK;
}

static sf_status set_param(void* instance, const char* name, const char* value, char* error, size_t size) {
    (void)instance, (void)name, (void)value, (void)error, (void)size;
    return SF_OK;
}

static sf_status execute_frame(void* instance, const sf_plugin_run* frame, char* error, size_t size) {
    (void)instance, (void)frame, (void)error, (void)size;
    return SF_OK;
}

static void release(void* instance) { (void)instance; }

static const sf_plugin plugin = {
    SF_PLUGIN_ABI_VERSION, "consumer", "1.0.0", "does nothing", SF_FILTER_SINGLE_FRAME, 0, NULL, NULL,
    create, set_param, NULL, release, SF_PLUGIN_THREAD_SAFE, execute_frame,
};

SF_PLUGIN_EXPORT const sf_plugin* sf_plugin_entry(void) { return &plugin; }
