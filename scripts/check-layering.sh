#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The module arrows of docs/architecture.md "Who uses whom", checked on the #include lines of the
# tracked sources; prints each include that points the wrong way and exits 1 when there is any.
set -euo pipefail
cd "$(dirname "$0")/.."
bad=0
# rule <module dir> <forbidden include regex> <why> [<paths excluded from the rule, space-separated>]
rule() {
    local dir="$1" pattern="$2" why="$3" except="${4:-}"
    local hits rc=0 excluded=()
    for e in $except; do excluded+=(":!$e"); done
    hits="$(git grep -n -P "$pattern" -- "$dir/*.cpp" "$dir/*.h" "${excluded[@]}")" || rc=$?
    if [ "$rc" -gt 1 ]; then echo "check-layering: git grep failed on $dir ($pattern)" >&2; exit 2; fi
    if [ -n "$hits" ]; then
        while IFS= read -r h; do echo "layering: $h ($why)"; done <<< "$hits"
        bad=$((bad + 1))
    fi
}
rule map '#include "navmap/(render|ipc|daemon|sim)/' "map/ depends on no other module"
rule map '#include "navmap/map/compile/' "map/'s run-time code does not use the offline map/compile" map/compile
for m in common ipc render sim daemon; do
    rule "$m" '#include "navmap/map/compile/' "navmapd's modules do not use the offline map/compile"
done
rule ipc '#include "navmap/(render|map|daemon|sim)/' "ipc/ does not know render/, map/, daemon/ or sim/"
# Inside ipc/: net at the bottom; client (libnavmap-client) on net alone; can and control on net;
# stream (the frame server) on client's wire format and net; gst (the GStreamer plugin) on client
# alone. ipc/CMakeLists.txt links the same way.
rule ipc/net '#include "navmap/ipc/(can|control|stream|client)/' "ipc/net uses no other part of ipc/"
rule ipc/client '#include "navmap/ipc/(can|control|stream)/' "ipc/client (libnavmap-client) uses ipc/net only"
rule ipc/can '#include "navmap/ipc/(control|stream|client)/' "ipc/can uses ipc/net only"
rule ipc/control '#include "navmap/ipc/(can|stream|client)/' "ipc/control uses ipc/net only"
rule ipc/stream '#include "navmap/ipc/(can|control)/' "ipc/stream uses ipc/client and ipc/net only"
rule ipc/gst '#include "navmap/ipc/(can|control|stream)/' "ipc/gst (navmapsrc) uses libnavmap-client only"
rule . '#include <(gst|glib|glib-object)[/.]' "GStreamer and GLib stay in ipc/gst and its tests" "ipc/gst tests/ipc/gst"
rule . '#include "navmap/ipc/[a-z_]+\.h"' "ipc/'s headers are navmap/ipc/<part>/<file>.h"
rule ipc '#include "navmap_client.h"' "only libnavmap-client's C API includes navmap_client.h" ipc/client
rule render '#include "navmap/(ipc|daemon|sim)/' "render/ uses map/ only"
rule sim '#include "navmap/render/' "sim/ does not render"
rule sim '#include "navmap/daemon/' "sim/ does not know the daemon (its CanSource is ipc's)"
rule daemon '#include "navmap/sim/' "the daemon gets the simulator as a SimulatorFactory" daemon/navmapd.cpp
# tests/support/dmabuf_import.cpp plays a display process that imports navmapd's dma-buf frames
# into its own EGL display: a GPU client, not the renderer.
rule . '#include <(GLES[23]|EGL)/' "GL and EGL stay in render/src/gl" "render/src/gl tests/support/dmabuf_import.cpp"
# libwayland-client is navmap-wayland's alone: not the client library, not the daemon.
rule . '#include (<wayland-|"[a-z-]+-client-protocol\.h")' "Wayland stays in ipc/client/wayland" "ipc/client/wayland"
rule ipc/client/wayland '#include "navmap/ipc/(can|control|stream)/' "navmap-wayland is a client: ipc/client and ipc/net only"
if [ "$bad" -gt 0 ]; then
    echo "check-layering: $bad rule(s) broken (docs/architecture.md \"Who uses whom\")"
    exit 1
fi
echo "check-layering: the includes follow docs/architecture.md \"Who uses whom\""
