#pragma once
// Private to the camera module: scene geometry as VTK polydata and mappers, for the colour pass
// (surface colours, "albedo") and the id pass (class and object, "id").
#include <array>
#include <cstdint>

#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkSmartPointer.h>

#include "trainsim/scene/scene.hpp"

namespace trainsim::camera {

// The id pass's colour of a surface: R the class, G and B the drawn object's slot + 1.
std::array<std::uint8_t, 3> idColour(scene::ClassId cls, std::uint32_t slot);

// A mapper drawing `poly` in the colours of its cell array `array`, as they are (static data).
vtkSmartPointer<vtkPolyDataMapper> colourMapper(vtkPolyData* poly, const char* array);

// Which of a mesh's triangles meshPolyData() takes: all, those that reflect light, or those
// that emit it (with their emission colours as albedo).
enum class Emitting { kAll, kNot, kOnly };

// Whether some part of `mesh` emits light.
bool anyEmits(const scene::Mesh& mesh);

// A mesh (the parts `which` takes) as polydata: float vertices relative to the mesh's origin,
// with its triangles' surface colours ("albedo"; emission colours for kOnly) and classes
// ("class").
vtkSmartPointer<vtkPolyData> meshPolyData(const scene::Mesh& mesh, Emitting which = Emitting::kAll);

// The id pass's polydata of one object at one level: the level's points and triangles (shared,
// not copied) with the object's own id colours.
vtkSmartPointer<vtkPolyData> idPolyData(vtkPolyData* mesh_poly, std::uint32_t slot);

// A wire as a polyline in both passes' colours.
vtkSmartPointer<vtkPolyData> wirePolyData(const scene::Wire& wire, std::uint32_t slot);

}  // namespace trainsim::camera
