# Third-party packages, all from Debian 12 (see scripts/debian-packages.txt).
# Heavy packages (VTK, PCL, Embree, CGAL) are found by the modules that use them and linked
# PRIVATE so their headers stay out of the public ones.
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(nlohmann_json 3.10 REQUIRED)
find_package(CLI11 REQUIRED)
find_package(fmt REQUIRED)
find_package(spdlog REQUIRED)
find_package(Threads REQUIRED)
# CGAL 5.5 (header-only with GMP/MPFR): the terrain's Delaunay simplification.
find_package(CGAL REQUIRED)
# libpng: 16-bit height maps and, later, depth, semantic and instance images.
find_package(PNG REQUIRED)
# Xlib: the camera checks that DISPLAY accepts connections before VTK, which aborts if not.
find_package(X11 REQUIRED)
# Embree 3.13 (Debian: ray masks on, one instance level, TBB tasking): the LiDAR's ray casting.
find_package(embree 3.13 REQUIRED)
# oneTBB: the run loop's worker arena (sim) and, later, the LiDAR's column split.
find_package(TBB REQUIRED)
# GeographicLib's Find module lives outside CMake's default search path on Debian.
list(APPEND CMAKE_MODULE_PATH /usr/share/cmake/geographiclib)
find_package(GeographicLib 2.1 REQUIRED)

# Random123 is header-only and ships no CMake config.
find_path(RANDOM123_INCLUDE_DIR Random123/philox.h REQUIRED)
add_library(Random123::Random123 INTERFACE IMPORTED)
target_include_directories(Random123::Random123 SYSTEM INTERFACE ${RANDOM123_INCLUDE_DIR})

if(TRAINSIM_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()

# VTK: the scene's ParaView export (IOXML) and the cameras' offscreen rendering (RenderingCore,
# RenderingOpenGL2) everywhere; the studio's Qt widgets. Debian's VTK config needs MPI's C
# component found first (docs/REFERENCES.md P5).
find_package(MPI COMPONENTS C)
set(TRAINSIM_VTK_COMPONENTS CommonCore CommonDataModel IOXML RenderingCore RenderingOpenGL2)
if(TRAINSIM_BUILD_TESTS)  # the cameras' image regression tests (PNGs, vtkImageDifference)
  list(APPEND TRAINSIM_VTK_COMPONENTS IOImage ImagingCore)
endif()
if(TRAINSIM_BUILD_STUDIO)
  list(APPEND TRAINSIM_VTK_COMPONENTS FiltersSources GUISupportQt InteractionStyle
       RenderingAnnotation RenderingFreeType)
endif()
find_package(VTK 9.1 REQUIRED COMPONENTS ${TRAINSIM_VTK_COMPONENTS})
# PCL 1.13: LiDAR scans as PCD files (io) and the tests' read-back. Its config needs MPI's C
# component too; only its libraries are used (not PCL_DEFINITIONS, which would set the ISA).
find_package(PCL 1.13 REQUIRED COMPONENTS common io)
# OpenCV 4.6: the cameras' lens distortion (undistortPoints, remap). Debian's config lives in
# libopencv-dev and checks that every module's library is installed.
find_package(OpenCV 4.6 REQUIRED COMPONENTS core imgproc calib3d)

# The studio's Qt 5 and QCustomPlot, found here so the GUI tests see the same targets.
if(TRAINSIM_BUILD_STUDIO)
  find_package(Qt5 5.15 REQUIRED COMPONENTS Widgets Concurrent PrintSupport Test)
  find_package(QCustomPlot REQUIRED)
endif()
