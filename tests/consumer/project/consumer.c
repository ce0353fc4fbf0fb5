/* Downstream use of the installed public API: versions match, errors are reported. */
#include <stdio.h>
#include <string.h>
#include <vbl/vbl.h>

int main(void)
{
    int major = -1, minor = -1, patch = -1;
    vbl_version(&major, &minor, &patch);
    if (major != VBL_VERSION_MAJOR || minor != VBL_VERSION_MINOR || patch != VBL_VERSION_PATCH) {
        fprintf(stderr, "header %s vs library %s\n", VBL_VERSION_STRING, vbl_version_string());
        return 1;
    }
    vbl_volume* volume = NULL;
    vbl_volume_load_options options = VBL_VOLUME_LOAD_OPTIONS_DEFAULT;
    vbl_result result = vbl_volume_load("/nonexistent/cloud.vdb", &options, &volume);
    if (result != VBL_ERROR_FILE_NOT_FOUND || !strstr(vbl_last_error_message(), "/nonexistent/cloud.vdb")) {
        fprintf(stderr, "unexpected: %s: %s\n", vbl_result_name(result), vbl_last_error_message());
        return 1;
    }
    printf("consumer ok: libvbl %s\n", vbl_version_string());
    return 0;
}
