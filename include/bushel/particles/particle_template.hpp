#pragma once
// A particle shape: one sphere or a rigid clump of overlapping spheres (docs/physics.md section 1),
// stored in its principal frame with the centre of mass at the origin. Mass properties are
// kept per unit density so one template serves any material.

#include <string>
#include <vector>

#include "bushel/core/quat.hpp"
#include "bushel/core/vec3.hpp"
#include "bushel/particles/sphere_element.hpp"

namespace bushel {

struct TemplateOptions {
  /// Grid columns across the clump's cross-section for the union integration; 400 gives
  /// volumes within about 1e-5 of the converged value for the wheat templates.
  int resolution = 400;
};

struct ParticleTemplate {
  std::string name;                    ///< e.g. "large_5s"
  std::vector<SphereElement> spheres;  ///< in the principal frame, centre of mass at the origin [m]
  double volume = 0.0;                 ///< volume of the union of the spheres [m3]
  Vec3 principal_moments;              ///< principal inertia per unit density, ascending [m5]
  Vec3 input_centroid;                 ///< centre of mass in the frame the spheres were given in [m]
  Quat principal_to_input;             ///< rotates principal-frame vectors into the input frame

  bool is_single_sphere() const { return spheres.size() == 1; }
  /// Mass [kg] for a solid density [kg/m3].
  double mass(double density) const { return density * volume; }
  /// Principal moments of inertia [kg m2] for a solid density [kg/m3].
  Vec3 principal_inertia(double density) const { return principal_moments * density; }
  /// Diameter of the sphere of equal volume [m].
  double equivalent_diameter() const;
  /// Extents along the principal axes [m]: x is the axis of least inertia (the length for
  /// an elongated kernel), z the axis of most inertia (the thickness).
  Vec3 extents() const;
  /// Length over width, extents().x / extents().y [-].
  double aspect_ratio() const;
  /// Radius of the smallest sphere element [m] (sets the Rayleigh time step).
  double min_sphere_radius() const;
  /// Distance from the centre of mass to the farthest sphere surface [m].
  double bounding_radius() const;
};

/// The range of a template sphere's radius [m], and of its centre's coordinates (up to the
/// largest radius) that make_template accepts.
inline constexpr double smallest_sphere_radius = 1e-6;
inline constexpr double largest_sphere_radius = 10.0;

/// Builds a template from spheres given in any body frame: computes the union volume,
/// centre of mass and inertia numerically, then re-expresses the spheres in the principal
/// frame (axes ordered by ascending moment, right-handed, signs canonical). Throws
/// InputError for no spheres, or a radius or centre out of those ranges (or not finite).
ParticleTemplate make_template(std::string name, std::vector<SphereElement> spheres,
                               const TemplateOptions& options = {});

}  // namespace bushel
