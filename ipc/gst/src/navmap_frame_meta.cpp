// SPDX-License-Identifier: Apache-2.0
#include "navmap_frame_meta.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>

namespace navmap::ipc::gst {

namespace {

gboolean metaInit(GstMeta* meta, gpointer /*params*/, GstBuffer* /*buffer*/) {
    auto* m = reinterpret_cast<GstNavmapFrameMeta*>(meta);
    // Everything after the GstMeta header zero; strings "" so that readers never see NULL.
    std::memset(reinterpret_cast<char*>(m) + sizeof(GstMeta), 0, sizeof(GstNavmapFrameMeta) - sizeof(GstMeta));
    m->next_type = g_strdup("");
    m->next_street = g_strdup("");
    m->current_street = g_strdup("");
    m->lane_count = -1;
    return TRUE;
}

void metaFree(GstMeta* meta, GstBuffer* /*buffer*/) {
    auto* m = reinterpret_cast<GstNavmapFrameMeta*>(meta);
    g_free(m->next_type);
    g_free(m->next_street);
    g_free(m->current_street);
}

void replaceString(gchar** field, const char* value) {
    g_free(*field);
    *field = g_strdup(value != nullptr ? value : "");
}

/// Copies every field of `from` into `to` (strings duplicated).
void copyFields(GstNavmapFrameMeta* to, const GstNavmapFrameMeta& from) {
    gchar* next_type = to->next_type;
    gchar* next_street = to->next_street;
    gchar* current_street = to->current_street;
    std::memcpy(reinterpret_cast<char*>(to) + sizeof(GstMeta), reinterpret_cast<const char*>(&from) + sizeof(GstMeta),
                sizeof(GstNavmapFrameMeta) - sizeof(GstMeta));
    to->next_type = next_type;
    to->next_street = next_street;
    to->current_street = current_street;
    replaceString(&to->next_type, from.next_type);
    replaceString(&to->next_street, from.next_street);
    replaceString(&to->current_street, from.current_street);
}

/// Buffer copies (gst_buffer_copy, a writable copy, copy_into with metadata) take the meta along:
/// it describes the frame, not its bytes, so a region copy keeps it too. Other transforms (a
/// scale, a crop) are refused, as for any meta that does not know them.
gboolean metaTransform(GstBuffer* dest, GstMeta* meta, GstBuffer* /*buffer*/, GQuark type, gpointer /*data*/) {
    if (!GST_META_TRANSFORM_IS_COPY(type)) {
        return FALSE;
    }
    auto* copy = reinterpret_cast<GstNavmapFrameMeta*>(gst_buffer_add_meta(dest, navmapFrameMetaInfo(), nullptr));
    if (copy == nullptr) {
        return FALSE;
    }
    copyFields(copy, *reinterpret_cast<const GstNavmapFrameMeta*>(meta));
    return TRUE;
}

std::string lanesText(const GstNavmapFrameMeta& m) {
    if (m.lane_count < 0) {
        return "unknown";
    }
    std::string text;
    for (int i = 0; i < m.lane_count; ++i) {
        char hex[8];
        std::snprintf(hex, sizeof(hex), "%s%02x", i > 0 ? "," : "", m.lanes[i]);
        text += hex;
    }
    return text;
}

}  // namespace

GType navmapFrameMetaApiType() {
    static GType type = 0;
    if (g_once_init_enter(&type)) {
        static const gchar* tags[] = {nullptr};  // none: not tied to the pixels' size, format or memory
        const GType t = gst_meta_api_type_register(GST_NAVMAP_FRAME_META_API_NAME, tags);
        g_once_init_leave(&type, t);
    }
    return type;
}

const GstMetaInfo* navmapFrameMetaInfo() {
    static const GstMetaInfo* info = nullptr;
    if (g_once_init_enter(&info)) {
        const GstMetaInfo* i = gst_meta_register(navmapFrameMetaApiType(), GST_NAVMAP_FRAME_META_INFO_NAME,
                                                 sizeof(GstNavmapFrameMeta), metaInit, metaFree, metaTransform);
        g_once_init_leave(&info, i);
    }
    return info;
}

GstNavmapFrameMeta* addNavmapFrameMeta(GstBuffer* buffer, const FrameHeader& header, const FrameMeta* block) {
    if (!header.validity.known() && block == nullptr) {
        return nullptr;
    }
    auto* m = reinterpret_cast<GstNavmapFrameMeta*>(gst_buffer_add_meta(buffer, navmapFrameMetaInfo(), nullptr));
    if (m == nullptr) {
        return nullptr;
    }
    m->sequence = header.sequence;
    m->validity_known = header.validity.known() ? TRUE : FALSE;
    m->flags = header.validity.flags;
    m->degraded = header.validity.degraded;
    m->pose_age_ms = header.validity.pose_age_ms;
    if (block == nullptr) {
        return m;
    }
    m->has_block = TRUE;
    m->has_pose = block->has_pose ? TRUE : FALSE;
    m->lat_deg = block->lat_deg;
    m->lon_deg = block->lon_deg;
    m->heading_deg = block->heading_deg;
    m->pose_time_ns = block->pose_time_ns;
    m->has_next = block->has_next ? TRUE : FALSE;
    const char* type_name = block->has_next ? metaManeuverName(block->next_type) : nullptr;
    replaceString(&m->next_type, type_name);
    m->next_exit = block->next_exit;
    m->next_distance_m = block->next_distance_m;
    replaceString(&m->next_street, block->next_street.c_str());
    m->lane_count = block->lanes_known ? static_cast<gint>(std::min(block->lanes.size(), sizeof(m->lanes))) : -1;
    for (gint i = 0; i < m->lane_count; ++i) {
        m->lanes[i] = block->lanes[static_cast<std::size_t>(i)];
    }
    m->has_remaining = block->has_remaining ? TRUE : FALSE;
    m->remaining_m = block->remaining_m;
    m->remaining_s = block->remaining_s;
    replaceString(&m->current_street, block->current_street.c_str());
    m->speed_limit_kmh = block->speed_limit_kmh;
    return m;
}

GstStructure* navmapFrameStructure(const GstNavmapFrameMeta* meta, std::uint64_t sequence, GstClockTime pts) {
    GstNavmapFrameMeta none{};
    none.next_type = none.next_street = none.current_street = const_cast<gchar*>("");
    none.lane_count = -1;
    const GstNavmapFrameMeta& m = meta != nullptr ? *meta : none;
    FrameValidity v;
    v.version = m.validity_known ? kFrameValidityVersion : 0;
    v.flags = static_cast<std::uint8_t>(m.flags);
    v.degraded = static_cast<std::uint16_t>(m.degraded);
    v.pose_age_ms = m.pose_age_ms;
    GstStructure* s =
        gst_structure_new("navmap-frame", "sequence", G_TYPE_UINT64, static_cast<guint64>(sequence), "pts",
                          G_TYPE_UINT64, static_cast<guint64>(pts), "validity", G_TYPE_STRING, validityText(v).c_str(),
                          "degraded", G_TYPE_STRING, degradedText(v.degraded).c_str(), "pose-age-ms", G_TYPE_UINT,
                          m.pose_age_ms, "meta", G_TYPE_BOOLEAN, m.has_block, nullptr);
    if (m.has_block == FALSE) {
        return s;
    }
    if (m.has_pose != FALSE) {
        gst_structure_set(s, "lat", G_TYPE_DOUBLE, m.lat_deg, "lon", G_TYPE_DOUBLE, m.lon_deg, "heading", G_TYPE_DOUBLE,
                          m.heading_deg, "pose-time-ns", G_TYPE_INT64, m.pose_time_ns, nullptr);
    }
    if (m.has_next != FALSE) {
        gst_structure_set(s, "next-type", G_TYPE_STRING, m.next_type, "next-exit", G_TYPE_INT, m.next_exit,
                          "next-distance-m", G_TYPE_DOUBLE, m.next_distance_m, "next-street", G_TYPE_STRING,
                          m.next_street, nullptr);
    }
    gst_structure_set(s, "lanes", G_TYPE_STRING, lanesText(m).c_str(), nullptr);
    if (m.has_remaining != FALSE) {
        gst_structure_set(s, "remaining-m", G_TYPE_DOUBLE, m.remaining_m, "remaining-s", G_TYPE_DOUBLE, m.remaining_s,
                          nullptr);
    }
    gst_structure_set(s, "street", G_TYPE_STRING, m.current_street, "speed-limit-kmh", G_TYPE_UINT, m.speed_limit_kmh,
                      nullptr);
    return s;
}

}  // namespace navmap::ipc::gst
