/* The scene's camera from JSON (docs/readme/render.md, "Camera"): the scene's "camera", a named
 * entry of "cameras" or a camera file (vbl_scene_load_options.camera), with a vertical fov or a
 * focal length + sensor + fit as in Blender, the resolution override, and "frame_media" (or
 * "camera": "auto"), which frames the media's bounding box from a direction. */
#ifndef VBL_SCENE_SCENE_CAMERA_H
#define VBL_SCENE_SCENE_CAMERA_H

#include "scene/scene.h"
#include "scene/scene_json.h"

typedef enum vbl_sensor_fit {
    VBL_SENSOR_FIT_AUTO = 0,       /* sensor_width spans the larger image dimension */
    VBL_SENSOR_FIT_HORIZONTAL = 1, /* sensor_width spans the image width */
    VBL_SENSOR_FIT_VERTICAL = 2    /* sensor_height spans the image height */
} vbl_sensor_fit;

/* tan(vertical fov / 2) of a lens (millimetres) on a width x height image, as Blender computes it. */
double vbl_camera_tan_half_vfov(double focal_length, double sensor_width, double sensor_height,
                                vbl_sensor_fit fit, int width, int height);

/* Parses the camera the options pick (the media must be loaded: frame_media reads their bounds). */
vbl_result vbl_scene_parse_camera(const vbl_json_ctx* ctx, const cJSON* root, const vbl_scene* scene,
                                  const vbl_scene_load_options* options, vbl_camera* cam);

#endif
