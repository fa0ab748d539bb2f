// C-12 airframe geometry (internal to the generator): the parts as
// parametric shapes plus the stations the livery needs.
#pragma once

#include "shapes.h"

namespace aar::scenes {

/// Stations s are metres aft of the fuselage nose tip; body x = reference_station - s.
struct C12Airframe {
  double reference_station;  ///< station of the reference point (MAC quarter chord)
  double mac;                ///< wing mean aerodynamic chord (m)
  double mac_span_station;   ///< |y| of the mean aerodynamic chord (m)
  double nacelle_y;          ///< |y| of the nacelle axes
  Body fuselage;
  LiftingSurface wing;
  Body nacelle_left;   ///< +y
  Body nacelle_right;  ///< -y
  LiftingSurface fin;
  LiftingSurface stabilizer;

  double StationOfX(double x) const { return reference_station - x; }
};

C12Airframe MakeC12Airframe();

}  // namespace aar::scenes
