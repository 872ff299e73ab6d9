#pragma once
// Reading a drawing (PNG or JPEG, told apart by their first bytes, not the file's name) into
// the grey pixels plan_from_image works on. Colour is turned to grey by luminance and any
// transparency is laid over white, as a drawing's background is.
#include <string>

#include "locus/imaging/plan_from_image.hpp"

namespace locus::tools {

// Throws std::runtime_error naming the file and what is wrong with it.
imaging::GreyImage read_grey_image(const std::string& path);

}  // namespace locus::tools
