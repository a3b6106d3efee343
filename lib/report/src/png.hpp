#pragma once
// Grab a VTK render window into a PNG file (atomically).
#include <string>

class vtkRenderWindow;

namespace laserfit::report {
void write_png(const std::string& path, vtkRenderWindow* window);
}
