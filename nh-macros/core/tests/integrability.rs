//! The integrability diagnosis: proved symbolically where the canonical form
//! decides, confirmed numerically where it cannot, and never claimed for a
//! nonholonomic system.
use quote::quote;

fn stats(body: proc_macro2::TokenStream) -> nh_core::Stats {
    let (out, stats) = nh_core::expand_with_stats(body);
    assert!(!out.to_string().contains("compile_error"), "{out}");
    stats
}

#[test]
fn rolling_on_a_line_is_integrable_by_proof() {
    let s = stats(quote! {
        struct LineWheel {
            parameters { m, R }
            coordinates { theta, x }
            lagrangian = m/2*dot(x)^2 + m*R^2/4*dot(theta)^2;
            constraints { dot(x) = R*dot(theta); }
        }
    });
    assert!(s.integrable && s.integrable_proved);
}

#[test]
fn an_exact_differential_with_coupled_coefficients_is_integrable_by_proof() {
    // dz = d(x² y + exp(x y)) = (2 x y + y e^{xy}) dx + (x² + x e^{xy}) dy
    let s = stats(quote! {
        struct Exact {
            coordinates { x, y, z }
            lagrangian = (dot(x)^2 + dot(y)^2 + dot(z)^2)/2;
            constraints { dot(z) = (2*x*y + y*exp(x*y))*dot(x) + (x^2 + x*exp(y*x))*dot(y); }
        }
    });
    assert!(s.integrable && s.integrable_proved);
}

#[test]
fn angle_addition_is_decided_numerically() {
    // dz = sin(x + y) (dx + dy) = d(−cos(x + y)), written with the addition formula on dy
    let s = stats(quote! {
        struct Addition {
            coordinates { x, y, z }
            lagrangian = (dot(x)^2 + dot(y)^2 + dot(z)^2)/2;
            constraints { dot(z) = sin(x + y)*dot(x) + (sin(x)*cos(y) + cos(x)*sin(y))*dot(y); }
        }
    });
    assert!(s.integrable, "the curvature vanishes");
    assert!(
        !s.integrable_proved,
        "the canonical form does not know the addition formula"
    );
}

#[test]
fn nonholonomic_systems_are_never_called_integrable() {
    let cases = [
        quote! {
            struct Disc {
                parameters { m, R, g }
                coordinates { theta, phi, psi, x, y }
                lagrangian = m/2*(dot(x)^2 + dot(y)^2) + m*R^2/4*dot(theta)^2 + m*R^2/8*dot(phi)^2 - m*g*R*cos(psi) + m*R^2/8*dot(psi)^2;
                constraints { dot(x) = R*cos(phi)*dot(theta); dot(y) = R*sin(phi)*dot(theta); }
            }
        },
        // a curvature that is tiny against its terms only at special points
        quote! {
            struct Nearly {
                coordinates { x, y, z }
                lagrangian = (dot(x)^2 + dot(y)^2 + dot(z)^2)/2;
                constraints { dot(z) = sin(x + y)*dot(x) + (sin(x)*cos(y) + cos(x)*sin(y) + x*y/1000000000)*dot(y); }
            }
        },
        // a curvature of e^-46 ≈ 1e-20 against terms of order one: below what f64
        // can tell from rounding, within reach of the 32-digit evaluation
        quote! {
            struct Barely {
                coordinates { x, y, z }
                lagrangian = (dot(x)^2 + dot(y)^2 + dot(z)^2)/2;
                constraints { dot(z) = sin(x + y)*dot(x) + (sin(x)*cos(y) + cos(x)*sin(y) + x*y*exp(-46))*dot(y); }
            }
        },
    ];
    for c in cases {
        let s = stats(c);
        assert!(!s.integrable);
    }
}
