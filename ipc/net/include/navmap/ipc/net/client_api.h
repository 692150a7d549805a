// SPDX-License-Identifier: Apache-2.0
#pragma once
// NAVMAP_CLIENT_API marks what libnavmap-client exports; everything else in it is hidden
// (-fvisibility=hidden), so its ABI is the documented API of stream_client.h,
// reconnecting_client.h and the headers they include.

#define NAVMAP_CLIENT_API __attribute__((visibility("default")))
