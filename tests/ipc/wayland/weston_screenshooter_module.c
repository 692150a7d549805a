// SPDX-License-Identifier: Apache-2.0
// A Weston 10 module for the tests under ivi-shell: it offers the weston_screenshooter global
// (screenshooter_create(), the same that desktop-shell calls), which ivi-shell does not, so that
// weston-screenshooter can capture the screen; with --debug any client may use it. Loaded with
// `weston --modules=<this file>`; never installed.
#include <weston/weston.h>

WL_EXPORT int wet_module_init(struct weston_compositor* compositor, int* argc, char* argv[]) {
    (void)argc;
    (void)argv;
    screenshooter_create(compositor);
    return 0;
}
