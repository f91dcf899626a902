#pragma once
// The project's default scene, generated procedurally into one .glb.
//
// Layout (glTF world: metres, +Y up, the camera looks along -Z, "north" = +Z):
//   - Camera 0 ("camera_main") at (0, ground + 5.5, 14), looking along -Z and
//     2.3 deg down, yfov 60 deg, znear 0.1. Ground height near the village is
//     within +-1 m of y = 0 (query it with `scene_generator --height X Z`).
//   - Village 20-150 m in front (z = -14 .. -145, x = -60 .. +45):
//       props at z -20 .. -40: a glass pane (BLEND) at (-4, -20) in front of a
//       polished metal sphere at (-4, -24) and a rough red sphere at (0.5, -24);
//       an emissive sign on steel posts at (7, -28) (matrix transform);
//       a double-sided thin wall at (-14, -34) whose back faces the camera;
//       a cut-out picket fence (MASK) along z = -40 from x = -30 to -6;
//       seven tree cards (MASK, one instanced mesh) around the village;
//     buildings: three instances of a gabled house (10 x 8 m, 6 m walls) at
//       (-24, -56), (34, -52), (-42, -96); a 24 m flat-roofed tower at
//       (22, -100); a 9 m flat-roofed block at (-5, -140).
//   - Rolling hills (+-5 m, 350 m wavelength) calm to +-1 m within ~150 m of
//     (0, -60); broad plains (+-80 m) beyond 1 km.
//   - Mountain range towards -Z: rising from z = -9 km, peaks 1.5-2.9 km high
//     between z = -15 and -45 km, falling off by -56 km; spans all x. Behind
//     the camera (+Z) and to the sides there are only plains and hills.
//   - Terrain covers x, z in [-65.5, 65.5] km.
//   - Sun: KHR_lights_punctual directional light, azimuth 120 deg (clockwise
//     from +Z towards +X), elevation 35 deg, 110000 lux: it stands front-right
//     of the camera, so shadows fall to the left and towards the camera.
#include <tiny_gltf.h>

namespace cr::gen {

constexpr double kSunAzimuthDeg = 120.0;
constexpr double kSunElevationDeg = 35.0;
constexpr double kSunIlluminanceLux = 110000.0;

// Builds the whole scene; detail >= 1 scales the terrain's triangle count.
tinygltf::Model build_default_scene(int detail);

}  // namespace cr::gen
