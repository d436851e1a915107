//! The other charts of a system take the multiplier route without deriving
//! the curvature route when the system's own chart chose it at under half
//! the curvature route's estimated cost (`generate::atlas::Charts`): the
//! hand-written rattleback's expansion went from about 348 ms to 197 ms
//! with cargo's default profiles.

/// The rattleback of `tests/convex.rs` with its contact written by hand.
const BY_HAND: &str = "
    pub struct ByHand {
        parameters { a1, a2, a3, h, m, A, B, C, delta, g }
        coordinates { psi, theta, phi, x, y }
        let R = rot_z(psi)*rot_y(theta)*rot_x(phi);
        let gam = transpose(R)*[0, 0, 1];
        let s = sqrt(a1^2*gam.x^2 + a2^2*gam.y^2 + a3^2*gam.z^2);
        let Cg = [x, y, s];
        let G = Cg + R*[0, 0, -h];
        let w = omega(R);
        let o = -(R*[a1^2*gam.x, a2^2*gam.y, a3^2*gam.z])/s;
        body shell { mass: m, centre: G, orientation: R, inertia: rot_z(delta)*diag(A, B, C)*transpose(rot_z(delta)) }
        lagrangian = kinetic_energy(shell) - m*g*G.z;
        constraints {
            dot(x) + cross(w, o).x = 0;
            dot(y) + cross(w, o).y = 0;
        }
    }";

#[test]
fn the_other_charts_follow_a_decisive_multiplier_route() {
    let (out, stats) = nh_core::expand_with_stats(BY_HAND.parse().expect("lexes"));
    let out = out.to_string();
    assert!(!out.contains("compile_error"), "{out}");
    // the own chart compares both routes and takes the multiplier route
    assert_eq!(stats.route, Some(nh_core::Route::Multiplier));
    assert!(
        stats.cost_curvature >= 2 * stats.cost_multiplier,
        "{stats:?}"
    );
    assert!(stats.charts.len() >= 2, "charts: {:?}", stats.charts);
    // its `accelerations` names the other route; the other charts' do not
    let compared = out.matches("(the other route needs").count();
    assert_eq!(compared, 1, "routes compared in {compared} charts");
}
