#pragma once
// The damping factor that makes a Hertzian impact rebound with the requested coefficient of
// restitution.
//
// docs/physics.md section 2 gives EDEM's factor, gamma = -2 sqrt(5/6) beta with
// beta = ln e / sqrt(ln^2 e + pi^2), in F_n = 4/3 E* sqrt(R*) delta^(3/2) + gamma sqrt(S_n m*) v_n,
// and also clamps a net attractive F_n to zero. Unclamped, that factor returns exactly e;
// clamped, the end of the contact (where damping would pull) is cut, and the rebound is
// livelier: e = 0.1 comes back as 0.25, e = 0.5 as 0.55. The model is scale free (the
// rebound does not depend on speed, size or stiffness), so one dimensionless impact,
// x'' = -max(0, x^(3/2) + gamma sqrt(3/2) x^(1/4) x'), fixes e(gamma); we invert it so the
// clamped law restores exactly the restitution the user asked for.

namespace bushel {

/// EDEM's factor -2 sqrt(5/6) beta(e) (exact for the unclamped law).
double edem_damping_factor(double restitution);

/// Restitution of one impact under the (clamped or unclamped) law with damping factor gamma.
double hertz_restitution(double gamma, bool clamp_attraction = true);

/// The gamma for which the clamped law rebounds with `restitution` (in (0, 1]); cached.
double damping_for_restitution(double restitution);

}  // namespace bushel
