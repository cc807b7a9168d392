#pragma once
// What surfcap-export shows a person: a contact sheet of the template and a few frames of every
// captured sequence, rendered from the front (+z) with their colours.
#include "surfcap/asset/character.hpp"
#include "surfcap/render/image.hpp"

namespace surfcap::asset {

struct PreviewOptions {
  int cell_width = 160;
  int cell_height = 240;
  int frames_per_sequence = 4;  ///< evenly spaced, first and last included
  int columns = 5;
};

render::Image character_preview(const Character& character, const PreviewOptions& options = {});

}  // namespace surfcap::asset
