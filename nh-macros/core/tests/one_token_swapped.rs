//! One mistake, one error: two neighbouring tokens of a valid system swapped,
//! at every position of a few systems (delimiters count as tokens; swaps the
//! lexer rejects are skipped), give at most one error, and no error spans
//! the whole input (or the macro call). `examples/swaps.rs` prints the same
//! figures for any file.
mod tokens;

use proc_macro2::TokenStream;
use tokens::{extent, flatten};

const SEEDS: &[&str] = &[
    r#"
    /// Rolling disc of the thesis.
    pub struct ThesisDisc {
        parameters { m, R, g }
        coordinates { theta, phi, psi, x, y }
        let X = x - R*sin(phi)*sin(psi);
        let Y = y + R*cos(phi)*sin(psi);
        let Z = R*cos(psi);
        lagrangian = m/2*(dot(X)^2 + dot(Y)^2 + dot(Z)^2)
                   + m*R^2/2*(dot(theta)^2/2 + dot(phi)^2/4 + dot(psi)^2/4)
                   - m*g*Z;
        constraints {
            dot(x) = R*cos(phi)*dot(theta);
            dot(y) = R*sin(phi)*dot(theta);
        }
        outputs { multipliers, curvature, energy }
    }"#,
    r#"
    pub struct PushedSled {
        parameters { m, J, a, c }
        coordinates { x, theta, y }
        inputs { push, steer }
        lagrangian = J*dot(theta)^2/2 + m/2*((dot(x) - a*sin(theta)*dot(theta))^2 + (dot(y) + a*cos(theta)*dot(theta))^2);
        constraints { cos(theta)*dot(y) - sin(theta)*dot(x) = 0; }
        dependent { y }
        forces { x: push*cos(theta) - c*dot(x); y: push*sin(theta) - c*dot(y); theta: steer; }
        outputs { routes, energy, multipliers, constraint_matrix, mass_matrix }
    }"#,
    r#"
    pub struct Snakeboard {
        parameters { m, J, Jr, l, c, b }
        coordinates { x, y, theta, psi }
        inputs { tau }
        lagrangian = m*(dot(x)^2 + dot(y)^2)/2 + J*dot(theta)^2/2 + Jr*(dot(theta) + dot(psi))^2/2;
        forces { x: -c*dot(x); psi: tau; }
        speeds { xi, w }
        kinematics {
            dot(x) = xi*cos(theta) + b*t;
            dot(y) = xi*sin(theta);
            dot(theta) = xi*tan(psi)/l;
            dot(psi) = w;
        }
        outputs { mass_matrix, reaction_forces, jacobian }
    }"#,
    r#"
    pub struct Robot {
        parameters { m, Ic, d, mw, Iw, Id, r, b }
        coordinates { x, y, theta, phi_l, phi_r }
        inputs { tau_l, tau_r }
        let O = [x, y, r];
        let axle = [-sin(theta), cos(theta), 0];
        body chassis { mass: m, centre: O + d*[cos(theta), sin(theta), 0], orientation: rot_z(theta), inertia: diag(0, 0, Ic) }
        body wheel_l { mass: mw, centre: O + b*axle, orientation: rot_z(theta)*rot_y(phi_l), inertia: diag(Id, Iw, Id) }
        body wheel_r { mass: mw, centre: O - b*axle, orientation: rot_z(theta)*rot_y(phi_r), inertia: diag(Id, Iw, Id) }
        lagrangian = kinetic_energy(chassis) + kinetic_energy(wheel_l) + kinetic_energy(wheel_r);
        constraints {
            rolls(wheel_l, radius: r, axle: [0, 1, 0]);
            rolls(wheel_r, radius: r, axle: [0, 1, 0]);
        }
        dependent { x, y, theta }
        forces { phi_l: tau_l; phi_r: tau_r; }
        outputs { energy, contact_points }
    }"#,
];

#[test]
fn one_swapped_token_gives_at_most_one_error_inside_the_input() {
    let mut expanded = 0;
    for seed in SEEDS {
        let input: TokenStream = seed.parse().expect("the seed lexes");
        assert!(
            nh_core::reported_errors(&nh_core::expand(input.clone())).is_empty(),
            "the seed is valid:\n{seed}"
        );
        let mut toks = Vec::new();
        flatten(input, &mut toks);
        for i in 0..toks.len() - 1 {
            if toks[i] == toks[i + 1] {
                continue;
            }
            let mut m = toks.clone();
            m.swap(i, i + 1);
            let text = m.join(" ");
            let Ok(input) = text.parse::<TokenStream>() else {
                continue;
            };
            expanded += 1;
            let (lo, hi) = extent(&input);
            let errors = nh_core::reported_errors(&nh_core::expand(input));
            let around = m[i.saturating_sub(6)..(i + 8).min(m.len())].join(" ");
            let messages: Vec<&str> = errors.iter().map(|e| e.message.as_str()).collect();
            assert!(
                errors.len() <= 1,
                "`{}` and `{}` swapped (… {around} …): {messages:#?}",
                toks[i],
                toks[i + 1]
            );
            for e in &errors {
                let (s, t) = (e.start.byte_range(), e.end.byte_range());
                assert!(
                    s.start >= lo && t.end <= hi && !(s.start == lo && t.end == hi),
                    "`{}` and `{}` swapped (… {around} …): the error spans the whole input or lies outside it: {}",
                    toks[i],
                    toks[i + 1],
                    e.message
                );
            }
        }
    }
    assert!(expanded > 700, "{expanded} swaps expanded");
}
