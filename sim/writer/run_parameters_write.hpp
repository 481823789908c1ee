// Writes the run file's /parameters group (runfile/run_parameters.hpp reads it
// back) from a validated scene, with the key tables the scene reader validates
// with; at the run's finish (writer/run_file.cpp).
#pragma once

#include "runfile/h5.hpp"
#include "scene/scene.hpp"

namespace dem2d {

void write_parameters(const h5::File& f, const Scene& scene);

}  // namespace dem2d
