//! Attributes on the system's struct that must hold for everything generated
//! for it reach every generated item: under `#[cfg(any())]` the system
//! vanishes entirely, its integrability warning included (the unit struct of
//! the same name below would otherwise receive its impls and fail, and
//! `deny(deprecated)` would fail on the warning); under `#[cfg(all())]` it is
//! there; a lint level set on the struct holds for the impls too (also under
//! `cfg_attr`). Other derives pass through, also under `cfg_attr`.
#![deny(dead_code, deprecated)]
use nonholonomic::prelude::*;

nonholonomic_system! {
    #[cfg(any())]
    pub struct Gone {
        parameters { m }
        coordinates { x, y }
        lagrangian = m/2*dot(x)^2 + m/2*dot(y)^2 - m*x*y;
        constraints { dot(y) = x*dot(x); }
    }
}

/// The name is free: the system above was configured away.
pub struct Gone;

nonholonomic_system! {
    #[cfg(all())]
    #[cfg_attr(all(), derive(PartialOrd))]
    pub struct Here {
        parameters { m, k }
        coordinates { x }
        lagrangian = m/2*dot(x)^2 - k/2*x^2;
    }
}

nonholonomic_system! {
    /// Never used: `allow(dead_code)` on it covers its methods too.
    #[allow(dead_code)]
    struct Unused {
        parameters { m }
        coordinates { x, y, z }
        lagrangian = m/2*(dot(x)^2 + dot(y)^2 + dot(z)^2) - m*z;
        constraints { dot(y) = z*dot(x); }
    }
}

nonholonomic_system! {
    /// Never used either: a lint level under `cfg_attr` reaches the methods too.
    #[cfg_attr(all(), allow(dead_code))]
    struct AlsoUnused {
        parameters { k }
        coordinates { x }
        lagrangian = dot(x)^2/2 - k*x^2/2;
    }
}

fn main() {
    let _ = Gone;
    let h = Here::new(2.0, 8.0);
    let a = h.accelerations(0.0, &SVector::from([0.5]), &SVector::from([0.0]));
    assert_eq!(a[0], -2.0);
    assert!(Here::new(1.0, 1.0) < Here::new(1.0, 2.0));
}
