//! Building and reading the state by name: the companions `NameCoordinates`,
//! `NameVelocities` and `NameParameters`, `state`, `split`,
//! `state_from_velocities`, `from_parameters` and `parameters`, and the
//! constants without a type argument. The velocities the constraints imply
//! are checked against their closed forms (the sled's ẏ = tan θ ẋ, the
//! pendulum's tangent, the turntable's ẋ = R φ̇_y − Ω y at time t).
use nonholonomic::prelude::*;

nonholonomic_system! {
    /// The Chaplygin sled: the blade at (x, y) moves along its heading θ.
    pub struct Sled {
        parameters { m, J, a }
        coordinates { x, theta, y }
        lagrangian = J*dot(theta)^2/2
            + m/2*((dot(x) - a*sin(theta)*dot(theta))^2 + (dot(y) + a*cos(theta)*dot(theta))^2);
        constraints { dot(y) = tan(theta)*dot(x); }
        outputs { energy }
    }
}

nonholonomic_system! {
    /// The same sled in the speed v of its blade and its yaw rate ω.
    pub struct SledSpeeds {
        parameters { m, J, a }
        coordinates { x, y, theta }
        lagrangian = J*dot(theta)^2/2
            + m/2*((dot(x) - a*sin(theta)*dot(theta))^2 + (dot(y) + a*cos(theta)*dot(theta))^2);
        speeds { v, omega }
        kinematics {
            dot(x) = v*cos(theta);
            dot(y) = v*sin(theta);
            dot(theta) = omega;
        }
    }
}

nonholonomic_system! {
    /// A pendulum in Cartesian coordinates: holonomic, solved for y.
    pub struct Pendulum {
        parameters { m, l, g }
        coordinates { x, y }
        lagrangian = m*(dot(x)^2 + dot(y)^2)/2 - m*g*y;
        constraints { x^2 + y^2 = l^2; }
    }
}

nonholonomic_system! {
    /// A ball rolling on a table turning at rate Omega: the constraints depend on time through the table.
    pub struct Turntable {
        parameters { m, R, Omega }
        coordinates { x, y, phix, phiy, phiz }
        lagrangian = m*(dot(x)^2 + dot(y)^2)/2 + m*R^2/5*(dot(phix)^2 + dot(phiy)^2 + dot(phiz)^2);
        constraints {
            dot(x) = R*dot(phiy) - Omega*y*(1 + t);
            dot(y) = -R*dot(phix) + Omega*x;
        }
    }
}

nonholonomic_system! {
    /// Keyword names as raw identifiers, and an input.
    pub struct Keywords {
        parameters { r#type, k }
        coordinates { r#loop, y }
        inputs { F }
        lagrangian = r#type/2*(dot(r#loop)^2 + dot(y)^2) - k/2*r#loop^2;
        forces { y: F; }
    }
}

nonholonomic_system! {
    /// No parameters at all.
    pub struct Free {
        coordinates { x }
        lagrangian = dot(x)^2/2;
    }
}

#[test]
fn the_state_from_named_parts_and_back() {
    let q = SledCoordinates {
        x: 1.0,
        theta: 0.2,
        y: -0.5,
    };
    let v = SledVelocities { x: 0.4, theta: 0.9 };
    let x0 = Sled::state(q, v);
    // [q, ṙ]: all coordinates, then the independent velocities ẋ, θ̇
    assert_eq!(x0, SVector::<f64, 5>::from([1.0, 0.2, -0.5, 0.4, 0.9]));
    assert_eq!(Sled::split(&x0), (q, v));
    assert_eq!(SVector::<f64, 3>::from(q), SVector::from([1.0, 0.2, -0.5]));
    assert_eq!(SledVelocities::from(SVector::<f64, 2>::from([0.4, 0.9])), v);
    let moved = SledCoordinates {
        theta: 1.0,
        ..SledCoordinates::default()
    };
    assert_eq!(
        <SVector<f64, 3>>::from(moved),
        SVector::from([0.0, 1.0, 0.0])
    );
}

#[test]
fn an_outcome_and_a_dense_output_sample_split_by_name() {
    let sled: Sled = Sled::new(2.0, 0.3, 0.5);
    let x0 = Sled::state(
        SledCoordinates {
            x: 0.0,
            theta: 0.2,
            y: 0.0,
        },
        SledVelocities { x: 0.4, theta: 0.9 },
    );
    let mut samples = Vec::new();
    let out = Dopri5::new(1e-10, 1e-12)
        .integrate_with_outputs(&sled, 0.0, x0, 2.0, &[1.0], |t, x| {
            samples.push((t, Sled::split(x)))
        })
        .unwrap();
    let (q, v) = Sled::split(&out.x);
    assert_eq!(
        [q.x, q.theta, q.y, v.x, v.theta],
        [out.x[0], out.x[1], out.x[2], out.x[3], out.x[4]]
    );
    // the energy by name equals the energy by vector
    let e = sled.energy(&q.into(), &v.into());
    assert!(
        (e - sled.energy(&x0.fixed_rows::<3>(0).into(), &x0.fixed_rows::<2>(3).into())).abs()
            < 1e-9
    );
    let (t1, (q1, _)) = samples[0];
    assert_eq!(t1, 1.0);
    assert!(
        q1.theta > 0.2 && q1.theta < q.theta,
        "θ grows monotonically: {q1:?} {q:?}"
    );
}

#[test]
fn velocities_that_satisfy_the_constraints_give_the_state() {
    let sled = Sled::new(2.0, 0.3, 0.5);
    let (th, xd, thd) = (0.7_f64, 0.4, -1.3);
    let q = SledCoordinates {
        x: 0.1,
        theta: th,
        y: 2.0,
    };
    let qdot = SledCoordinates {
        x: xd,
        theta: thd,
        y: th.tan() * xd,
    };
    let x = sled.state_from_velocities(q, qdot).unwrap();
    assert_eq!(x, Sled::state(q, SledVelocities { x: xd, theta: thd }));
}

#[test]
fn velocities_that_break_the_constraints_are_refused_with_the_coordinate() {
    let sled = Sled::new(2.0, 0.3, 0.5);
    let (th, xd) = (0.7_f64, 0.4);
    let q = SledCoordinates {
        x: 0.0,
        theta: th,
        y: 0.0,
    };
    // the blade slides sideways: ẏ ≠ tan θ ẋ
    let e = sled
        .state_from_velocities(
            q,
            SledCoordinates {
                x: xd,
                theta: 0.0,
                y: 0.5,
            },
        )
        .unwrap_err();
    assert_eq!(e.coordinate, "y");
    assert_eq!(e.given, 0.5);
    assert!((e.implied - th.tan() * xd).abs() < 1e-15);
    assert_eq!(e.tolerance, 0.5 * 1e-9);
    assert!(
        e.to_string()
            .starts_with("the velocity of `y` is 0.5 but the constraints give 0.33"),
        "{e}"
    );
    // rounding is not a violation; 1e-8 of the largest velocity is
    let ydot = th.tan() * xd;
    assert!(
        sled.state_from_velocities(
            q,
            SledCoordinates {
                x: xd,
                theta: 0.0,
                y: ydot * (1.0 + 1e-12)
            }
        )
        .is_ok()
    );
    assert!(
        sled.state_from_velocities(
            q,
            SledCoordinates {
                x: xd,
                theta: 0.0,
                y: ydot * (1.0 + 1e-8)
            }
        )
        .is_err()
    );
}

#[test]
fn a_holonomic_constraint_checks_the_tangent() {
    let p = Pendulum::new(1.0, 1.3, 9.81);
    assert_eq!(Pendulum::DEPENDENT, [1]);
    let th = 0.5_f64;
    let q = PendulumCoordinates {
        x: 1.3 * th.sin(),
        y: -1.3 * th.cos(),
    };
    // the bob swings at θ̇ = 2: (ẋ, ẏ) = 1.3·2·(cos θ, sin θ)
    let qdot = PendulumCoordinates {
        x: 2.6 * th.cos(),
        y: 2.6 * th.sin(),
    };
    let x = p.state_from_velocities(q, qdot).unwrap();
    assert_eq!(
        x,
        Pendulum::state(q, PendulumVelocities { x: 2.6 * th.cos() })
    );
    let radial = PendulumCoordinates {
        x: 2.6 * th.cos(),
        y: 0.0,
    };
    let e = p.state_from_velocities(q, radial).unwrap_err();
    assert_eq!(e.coordinate, "y");
    assert!((e.implied - 2.6 * th.sin()).abs() < 1e-15);
}

#[test]
fn time_dependent_constraints_take_the_time() {
    let (r, omega) = (0.2, 0.7);
    let ball = Turntable::new(1.0, r, omega);
    let q = TurntableCoordinates {
        x: 0.3,
        y: -0.4,
        phix: 0.0,
        phiy: 0.0,
        phiz: 0.0,
    };
    let (t, phixd, phiyd) = (2.0, 1.5, -0.5);
    let qdot = TurntableCoordinates {
        x: r * phiyd - omega * q.y * (1.0 + t),
        y: -r * phixd + omega * q.x,
        phix: phixd,
        phiy: phiyd,
        phiz: 3.0,
    };
    let x = ball.state_from_velocities(t, q, qdot).unwrap();
    assert_eq!(
        Turntable::split(&x).1,
        TurntableVelocities {
            phix: phixd,
            phiy: phiyd,
            phiz: 3.0
        }
    );
    // the same velocities at another time break the constraint of x
    assert_eq!(
        ball.state_from_velocities(0.0, q, qdot)
            .unwrap_err()
            .coordinate,
        "x"
    );
}

#[test]
fn speeds_from_the_velocities_of_the_coordinates() {
    let s = SledSpeeds::new(2.0, 0.3, 0.5);
    assert_eq!(SledSpeeds::SPEEDS, ["v", "omega"]);
    let (th, v, w) = (1.2_f64, 0.8, -0.3);
    let q = SledSpeedsCoordinates {
        x: 0.0,
        y: 1.0,
        theta: th,
    };
    let qdot = SledSpeedsCoordinates {
        x: v * th.cos(),
        y: v * th.sin(),
        theta: w,
    };
    let x = s.state_from_velocities(0.0, q, qdot).unwrap();
    let (q1, u) = SledSpeeds::split(&x);
    assert_eq!(q1, q);
    assert!(
        (u.v - v).abs() < 1e-15 && (u.omega - w).abs() < 1e-15,
        "{u:?}"
    );
    assert!((SledSpeeds::state(q, SledSpeedsVelocities { v, omega: w }) - x).amax() < 1e-15);
    // sliding sideways at θ = 0: ẏ ≠ 0 cannot come from any speed
    let q0 = SledSpeedsCoordinates { theta: 0.0, ..q };
    let e = s
        .state_from_velocities(
            0.0,
            q0,
            SledSpeedsCoordinates {
                x: 1.0,
                y: 0.5,
                theta: 0.2,
            },
        )
        .unwrap_err();
    assert_eq!((e.coordinate, e.given, e.implied), ("y", 0.5, 0.0));
}

#[test]
fn parameters_by_name() {
    let by_name = Sled::from_parameters(SledParameters {
        m: 2.0,
        J: 0.3,
        a: 0.5,
    });
    assert_eq!(by_name, Sled::new(2.0, 0.3, 0.5));
    let from: Sled = SledParameters {
        a: 0.5,
        J: 0.3,
        m: 2.0,
    }
    .into();
    assert_eq!(from, by_name);
    assert_eq!(
        by_name.parameters(),
        SledParameters {
            m: 2.0,
            J: 0.3,
            a: 0.5
        }
    );
    let free: Free = Free::from_parameters(FreeParameters::default());
    assert_eq!(free, Free::new());
    assert_eq!(free.parameters(), FreeParameters::default());
}

#[test]
fn keywords_as_raw_fields_and_systems_with_inputs() {
    let s: Keywords = Keywords::from_parameters(KeywordsParameters {
        r#type: 2.0,
        k: 8.0,
    });
    assert_eq!(s.parameters().r#type, 2.0);
    let x0 = Keywords::state(
        KeywordsCoordinates {
            r#loop: 1.0,
            y: 0.0,
        },
        KeywordsVelocities {
            r#loop: 0.0,
            y: 0.0,
        },
    );
    let qdot = KeywordsCoordinates {
        r#loop: 0.0,
        y: 0.0,
    };
    assert_eq!(
        s.state_from_velocities(
            KeywordsCoordinates {
                r#loop: 1.0,
                y: 0.0
            },
            qdot
        ),
        Ok(x0)
    );
    // held force F = 2 on y: ÿ = 1; the spring on `loop`: ẍ = −4 x
    let out = Rk4::new(1e-3)
        .integrate(&Driven::new(&s, SVector::from([2.0])), 0.0, x0, 1.0)
        .unwrap();
    let (q, v) = Keywords::split(&out.x);
    assert!((q.y - 0.5).abs() < 1e-12 && (v.y - 1.0).abs() < 1e-12);
    assert!((q.r#loop - 2.0_f64.cos()).abs() < 1e-10);
}

/// The constants do not depend on the scalar: generic code reads them as
/// `Sled::N` too.
fn dimension<T: RealField + Copy>(_sled: &Sled<T>) -> usize {
    Sled::STATE_DIM
}

#[test]
fn constants_without_a_type_argument() {
    assert_eq!(Sled::COORDINATES, ["x", "theta", "y"]);
    assert_eq!(Sled::INDEPENDENT, [0, 1]);
    assert_eq!(Sled::DEPENDENT, [2]);
    assert_eq!((Sled::N, Sled::K, Sled::P, Sled::STATE_DIM), (3, 2, 1, 5));
    const { assert!(!Sled::INTEGRABLE) };
    assert_eq!(Keywords::INPUTS, ["F"]);
    assert_eq!(Keywords::COORDINATES, ["loop", "y"]);
    // as before, with the type argument
    assert_eq!(Sled::<f64>::COORDINATES, Sled::COORDINATES);
    // in a constant context
    let zeros = [0.0_f64; Sled::STATE_DIM];
    assert_eq!(zeros.len(), 5);
    assert_eq!(dimension(&Sled::<f32>::new(2.0, 0.3, 0.5)), 5);
}

#[test]
fn another_scalar() {
    let sled = Sled::<f32>::new(2.0, 0.3, 0.5);
    let q = SledCoordinates::<f32> {
        x: 0.0,
        theta: 0.2,
        y: 0.0,
    };
    let x = sled
        .state_from_velocities(
            q,
            SledCoordinates {
                x: 0.4,
                theta: 0.9,
                y: 0.2f32.tan() * 0.4,
            },
        )
        .unwrap();
    assert_eq!(Sled::split(&x).1, SledVelocities { x: 0.4, theta: 0.9 });
}

/// A user's constants named like the new methods' arguments do not change
/// them (the arguments bind, they do not match the constants).
#[allow(non_upper_case_globals, dead_code)]
mod crowded {
    use nonholonomic::prelude::*;
    const v: f64 = 1.0;
    const qdot: u8 = 0;
    static parameters: f64 = 0.0;
    const q: i32 = 3;

    nonholonomic_system! {
        pub struct Crowded {
            parameters { m }
            coordinates { x, y, theta }
            lagrangian = m*(dot(x)^2 + dot(y)^2 + dot(theta)^2)/2;
            constraints { dot(y) = theta*dot(x); }
        }
    }

    #[test]
    fn arguments_bind() {
        let s = Crowded::from_parameters(CrowdedParameters { m: 1.0 });
        let at = CrowdedCoordinates {
            x: 1.0,
            y: 2.0,
            theta: 2.0,
        };
        let x = Crowded::state(at, CrowdedVelocities { x: 3.0, theta: 0.5 });
        assert_eq!(Crowded::split(&x).1.x, 3.0);
        let given = CrowdedCoordinates {
            x: 3.0,
            y: 6.0,
            theta: 0.5,
        };
        assert_eq!(s.state_from_velocities(at, given), Ok(x));
    }
}

#[test]
fn a_system_inside_a_function() {
    nonholonomic_system! {
        /// A harmonic oscillator, local to this function.
        struct Local {
            parameters { k }
            coordinates { x }
            lagrangian = dot(x)^2/2 - k*x^2/2;
        }
    }
    let s: Local = Local::from_parameters(LocalParameters { k: 4.0 });
    let x0 = Local::state(LocalCoordinates { x: 1.0 }, LocalVelocities { x: 0.0 });
    let out = Dop853::new(1e-12, 1e-14)
        .integrate(&s, 0.0, x0, 1.0)
        .unwrap();
    let (q, v) = Local::split(&out.x);
    // x = cos 2t
    assert!((q.x - 2.0_f64.cos()).abs() < 1e-10 && (v.x + 2.0 * 2.0_f64.sin()).abs() < 1e-10);
}
