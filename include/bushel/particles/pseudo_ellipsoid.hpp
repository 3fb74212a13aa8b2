#pragma once
// Pseudo-ellipsoid clumps: n spheres on the long axis of a kernel, the way the reference
// study built its 5- and 7-sphere wheat models by hand, made reproducible.
//
// Construction (a = length/2, b = width/2, spheres centred on x, equally spaced):
//  - the end spheres reach the kernel's tips (x_end + r_end = a) and by default have the
//    tip's radius of curvature of the ellipse, r_end = b^2 / a;
//  - the central sphere (two for even n) has radius b, so the width is matched;
//  - the spheres between start on the ellipse, r = b sqrt(1 - x^2/a^2), and, when a target
//    mass is given, are scaled together (never beyond b) until the union's mass equals it.
//    With n = 3 or 4 there are no such spheres and the end radius is adjusted instead.
// One sphere gives the sphere of equal volume (equal mass when a mass is given).
// For the large wheat kernel (6.12 x 3.05 mm, 0.0346 g) this gives interior radii within 2%
// of the study's large_5s.

#include <optional>
#include <string>

#include "bushel/particles/particle_template.hpp"

namespace bushel {

struct PseudoEllipsoidSpec {
  double length = 0.0;               ///< end-to-end kernel length [m]
  double width = 0.0;                ///< kernel width, the clump's largest diameter [m]
  int spheres = 5;                   ///< number of spheres: 1, or 3 and more
  std::optional<double> mass;        ///< target mass [kg]; none keeps the ellipse profile
  double density = 1373.0;           ///< solid density [kg/m3], converts the target mass to a volume
  std::optional<double> end_radius;  ///< radius of the end spheres [m]; default b^2/a
};

/// Builds the clump; throws InputError (keyed by the spec's field) for a bad spec or a
/// target mass outside what the construction can reach (the message gives the range).
ParticleTemplate make_pseudo_ellipsoid(const PseudoEllipsoidSpec& spec, std::string name,
                                       const TemplateOptions& options = {});

}  // namespace bushel
