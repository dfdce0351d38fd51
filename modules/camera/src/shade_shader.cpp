#include "shade_shader.hpp"

#include <string>

#include <vtkOpenGLShaderProperty.h>
#include <vtkShaderProgram.h>

namespace trainsim::camera {
namespace {

// Lights 0 … day_lights − 1 are the day's, the rest the shade's; `lit` false: a surface drawn
// without lights (a wire), its colour scaled by the ambient alone.
std::string shadeDeclarations(bool lit, int day_lights) {
  std::string s =
      "//VTK::TMap::Dec\n"
      "uniform sampler2D trainsimShares;\n"
      "uniform int trainsimShaded;\n"
      "uniform vec4 trainsimLight;\n"
      "float trainsimDay = 1.0;\n"
      "#define ambientIntensity mix(trainsimLight.y, trainsimLight.x, trainsimDay)\n";
  s += lit ? "#define diffuseIntensity 1.0\n" : "#define diffuseIntensity 0.0\n";
  for (int i = 0; lit && i < kMostLights; ++i)
    s += "#define lightColor" + std::to_string(i) + " (lightColor" + std::to_string(i) +
         (i < day_lights ? " * (trainsimDay * trainsimLight.z))\n"
                         : " * ((1.0 - trainsimDay) * trainsimLight.w))\n");
  return s;
}

}  // namespace

void setShadeShader(vtkOpenGLShaderProperty* p, bool lit, int day_lights) {
  p->ClearAllFragmentShaderReplacements();
  p->AddFragmentShaderReplacement("//VTK::TMap::Dec", true, shadeDeclarations(lit, day_lights),
                                  false);
  p->AddFragmentShaderReplacement(
      "//VTK::UniformFlow::Impl", true,
      "//VTK::UniformFlow::Impl\n"
      "  if (trainsimShaded == 1)\n"
      "    trainsimDay = texelFetch(trainsimShares, ivec2(gl_FragCoord.xy), 0).r;\n",
      false);
}

void setShadeUniforms(vtkObject*, unsigned long, void* client, void* program) {
  const auto& in = *static_cast<const ShadeInputs*>(client);
  auto* p = static_cast<vtkShaderProgram*>(program);
  p->SetUniformi("trainsimShares", in.unit);
  p->SetUniformi("trainsimShaded", in.shaded);
  p->SetUniform4f("trainsimLight", in.light.data());
}

}  // namespace trainsim::camera
