#include "scene_polydata.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>

#include "trainsim/scene/semantics.hpp"

namespace trainsim::app {

ScenePolyData scenePolyData(const std::vector<std::shared_ptr<const scene::Tile>>& tiles,
                            const Eigen::Vector3d& origin, SceneColour colour) {
  vtkNew<vtkPoints> points, wire_points;  // apart, so that the wires' mapper uploads only theirs
  vtkNew<vtkCellArray> polys, lines;
  vtkNew<vtkUnsignedCharArray> poly_colours, line_colours;
  poly_colours->SetNumberOfComponents(3);
  line_colours->SetNumberOfComponents(3);
  const auto colourOf = [&](scene::ClassId cls, scene::MaterialId material) {
    return colour == SceneColour::kClass ? scene::semanticClass(cls).colour
                                         : scene::material(material).colour;
  };
  ScenePolyData out;
  for (const auto& tile : tiles) {
    for (const scene::Wire& wire : tile->wires) {
      const vtkIdType base = wire_points->GetNumberOfPoints();
      for (const auto& p : wire.points) {
        const Eigen::Vector3d w = tile->origin + p.cast<double>() - origin;
        wire_points->InsertNextPoint(w.data());
      }
      lines->InsertNextCell(static_cast<vtkIdType>(wire.points.size()));
      for (std::size_t k = 0; k < wire.points.size(); ++k)
        lines->InsertCellPoint(base + static_cast<vtkIdType>(k));
      // Contact and messenger wires in dark grey in a camera's colours: their copper's colour
      // is lost against the sky at the width they are drawn.
      const scene::Rgb c = colour == SceneColour::kMaterial && wire.cls == scene::cls::kWire
                               ? scene::Rgb{40, 40, 40}
                               : colourOf(wire.cls, wire.material);
      line_colours->InsertNextTypedTuple(c.data());
    }
    for (const scene::Object& object : tile->objects) {
      const vtkIdType base = points->GetNumberOfPoints();
      const Eigen::Matrix3d linear = object.linear.cast<double>();
      for (const auto& v : object.mesh->vertices) {
        const Eigen::Vector3d w = object.position - origin + linear * v.cast<double>();
        points->InsertNextPoint(w.data());
      }
      for (const auto& part : object.mesh->parts) {
        const scene::Rgb c = colourOf(part.cls, part.material);
        for (std::uint32_t t = part.first_triangle; t < part.first_triangle + part.triangle_count;
             ++t) {
          const auto& tri = object.mesh->triangles[t];
          const vtkIdType ids[3] = {base + tri[0], base + tri[1], base + tri[2]};
          polys->InsertNextCell(3, ids);
          poly_colours->InsertNextTypedTuple(c.data());
        }
        out.triangles += part.triangle_count;
      }
    }
  }
  out.surfaces = vtkSmartPointer<vtkPolyData>::New();
  out.surfaces->SetPoints(points);
  out.surfaces->SetPolys(polys);
  out.surfaces->GetCellData()->SetScalars(poly_colours);
  out.wires = vtkSmartPointer<vtkPolyData>::New();
  out.wires->SetPoints(wire_points);
  out.wires->SetLines(lines);
  out.wires->GetCellData()->SetScalars(line_colours);
  return out;
}

}  // namespace trainsim::app
