// SPDX-License-Identifier: Apache-2.0
#pragma once
// The order in which land-cover areas are painted over each other (tag_rules.cpp).

#include "navmap/map/tag_rules.h"

namespace navmap::map {

/// Lowest first: the sea under everything mapped on land (harbours, piers, beaches), then large
/// natural classes, built-up, parks and sports, wetland, and water last so rivers stay visible.
/// The terrain's land-cover texture and the orthoimage's super land cover both paint in this
/// order.
int areaDrawOrder(AreaClass cls);

}  // namespace navmap::map
