/// @file StyledLayers.h
/// @brief A labelled asset as render layers: each styled structure on its own with
/// its colour and opacity, then the other structures with the base classification.
#pragma once

#include "pipeline/GaussianAsset.h"
#include "pipeline/LabelStyle.h"
#include "render/RenderVolume.h"
#include "render/SliceStack.h"

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace gvr {

struct StyledLayers {
    std::vector<std::unique_ptr<RenderVolume>> volumes;  ///< what the layers draw
    std::vector<StackLayer> layers;                      ///< point into @a volumes
};

/// @param styles  by structure id or name, as LabelStyleFile.h reads them
/// @param stylesName  names the styles in errors (their file)
/// @param minScaleVoxels  as for GaussianRenderVolume
/// @throw InputError naming @a stylesName for an unknown structure, or for a colour
///        on an RGB asset (whose structures keep their own colours).
StyledLayers styledLayers(const GaussianAsset& asset, const std::map<std::string, LabelStyle>& styles,
                          const Classifier& base, float minScaleVoxels, const std::string& stylesName);

}  // namespace gvr
