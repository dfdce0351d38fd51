#include "vtk_meshes.hpp"

#include <algorithm>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkUnsignedCharArray.h>

namespace trainsim::camera {

std::array<std::uint8_t, 3> idColour(scene::ClassId cls, std::uint32_t slot) {
  const std::uint32_t object = slot + 1;
  return {static_cast<std::uint8_t>(cls), static_cast<std::uint8_t>(object >> 8),
          static_cast<std::uint8_t>(object & 0xFF)};
}

vtkSmartPointer<vtkPolyDataMapper> colourMapper(vtkPolyData* poly, const char* array) {
  auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
  mapper->SetInputData(poly);
  mapper->SetScalarModeToUseCellFieldData();
  mapper->SelectColorArray(array);
  mapper->SetColorModeToDirectScalars();
  mapper->ScalarVisibilityOn();
  mapper->StaticOn();  // the data never changes: skip the pipeline's update checks
  return mapper;
}

bool anyEmits(const scene::Mesh& mesh) {
  return std::any_of(mesh.parts.begin(), mesh.parts.end(), [](const scene::MeshPart& part) {
    return scene::material(part.material).emits();
  });
}

vtkSmartPointer<vtkPolyData> meshPolyData(const scene::Mesh& mesh, Emitting which) {
  const auto taken = [which](const scene::MeshPart& part) {
    return which == Emitting::kAll ||
           scene::material(part.material).emits() == (which == Emitting::kOnly);
  };
  std::size_t cells = 0;
  for (const scene::MeshPart& part : mesh.parts)
    cells += taken(part) ? part.triangle_count : 0;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToFloat();
  points->SetNumberOfPoints(static_cast<vtkIdType>(mesh.vertices.size()));
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
    points->SetPoint(static_cast<vtkIdType>(i), mesh.vertices[i].x(), mesh.vertices[i].y(),
                     mesh.vertices[i].z());
  vtkNew<vtkCellArray> polys;
  polys->AllocateExact(static_cast<vtkIdType>(cells), static_cast<vtkIdType>(3 * cells));
  vtkNew<vtkUnsignedCharArray> albedo;
  albedo->SetName("albedo");
  albedo->SetNumberOfComponents(3);
  albedo->SetNumberOfTuples(static_cast<vtkIdType>(cells));
  vtkNew<vtkUnsignedCharArray> cls;
  cls->SetName("class");
  cls->SetNumberOfTuples(static_cast<vtkIdType>(cells));
  vtkIdType cell = 0;
  for (const scene::MeshPart& part : mesh.parts) {
    if (!taken(part))
      continue;
    const scene::Material& m = scene::material(part.material);
    const scene::Rgb c = which == Emitting::kOnly ? m.emission : m.colour;
    for (std::uint32_t t = part.first_triangle; t < part.first_triangle + part.triangle_count;
         ++t, ++cell) {
      const auto& tri = mesh.triangles[t];
      const vtkIdType ids[3] = {tri[0], tri[1], tri[2]};
      polys->InsertNextCell(3, ids);
      albedo->SetTypedTuple(cell, c.data());
      cls->SetValue(cell, part.cls);
    }
  }
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetPolys(polys);
  poly->GetCellData()->AddArray(albedo);
  poly->GetCellData()->AddArray(cls);
  return poly;
}

vtkSmartPointer<vtkPolyData> idPolyData(vtkPolyData* mesh_poly, std::uint32_t slot) {
  vtkNew<vtkUnsignedCharArray> ids;
  ids->SetName("id");
  ids->SetNumberOfComponents(3);
  const vtkIdType n = mesh_poly->GetNumberOfCells();
  ids->SetNumberOfTuples(n);
  auto* cls = vtkUnsignedCharArray::SafeDownCast(mesh_poly->GetCellData()->GetArray("class"));
  for (vtkIdType t = 0; t < n; ++t)
    ids->SetTypedTuple(t, idColour(cls->GetValue(t), slot).data());
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(mesh_poly->GetPoints());
  poly->SetPolys(mesh_poly->GetPolys());
  poly->GetCellData()->AddArray(ids);
  return poly;
}

vtkSmartPointer<vtkPolyData> wirePolyData(const scene::Wire& wire, std::uint32_t slot) {
  vtkNew<vtkPoints> points;
  points->SetDataTypeToFloat();
  for (const Eigen::Vector3f& p : wire.points)
    points->InsertNextPoint(p.x(), p.y(), p.z());
  vtkNew<vtkCellArray> lines;
  lines->InsertNextCell(static_cast<vtkIdType>(wire.points.size()));
  for (std::size_t k = 0; k < wire.points.size(); ++k)
    lines->InsertCellPoint(static_cast<vtkIdType>(k));
  vtkNew<vtkUnsignedCharArray> albedo, ids;
  albedo->SetName("albedo");
  albedo->SetNumberOfComponents(3);
  albedo->InsertNextTypedTuple(scene::material(wire.material).colour.data());
  ids->SetName("id");
  ids->SetNumberOfComponents(3);
  ids->InsertNextTypedTuple(idColour(wire.cls, slot).data());
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetLines(lines);
  poly->GetCellData()->AddArray(albedo);
  poly->GetCellData()->AddArray(ids);
  return poly;
}

}  // namespace trainsim::camera
