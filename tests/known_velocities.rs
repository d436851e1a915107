//! The state from the velocities a user knows for some coordinates
//! (`state_from_known_velocities`), against closed forms.

use nonholonomic::prelude::*;

nonholonomic_system! {
    /// A differential drive (unicycle kinematics): axle midpoint (x, y),
    /// heading θ, wheel angles; wheel radius r, half track b.
    pub struct Drive {
        parameters { m, J, Iw, r, b }
        coordinates { x, y, theta, left, right }
        lagrangian = m/2*(dot(x)^2 + dot(y)^2) + J/2*dot(theta)^2 + Iw/2*(dot(left)^2 + dot(right)^2);
        constraints {
            dot(x) = r/2*(dot(left) + dot(right))*cos(theta);
            dot(y) = r/2*(dot(left) + dot(right))*sin(theta);
            dot(theta) = r/(2*b)*(dot(right) - dot(left));
        }
    }
}

fn drive() -> Drive {
    Drive::from_parameters(DriveParameters {
        m: 3.0,
        J: 0.2,
        Iw: 0.01,
        r: 0.05,
        b: 0.2,
    })
}

#[test]
fn the_wheel_rates_follow_from_the_forward_speed_and_the_turn_rate() {
    let d = drive();
    let theta: f64 = 0.7;
    let q = DriveCoordinates {
        x: 1.0,
        y: 2.0,
        theta,
        left: 0.0,
        right: 0.0,
    };
    let (v, w) = (0.4, 0.8);
    let known = DriveCoordinates {
        x: Some(v * theta.cos()),
        y: None,
        theta: Some(w),
        left: None,
        right: None,
    };
    let state = d.state_from_known_velocities(q, known).unwrap();
    let (_, rates) = Drive::split(&state);
    let (left, right) = ((v - d.b * w) / d.r, (v + d.b * w) / d.r);
    assert!(
        (rates.left - left).abs() < 1e-12 * left.abs(),
        "{} vs {left}",
        rates.left
    );
    assert!(
        (rates.right - right).abs() < 1e-12 * right.abs(),
        "{} vs {right}",
        rates.right
    );
}

#[test]
fn too_few_or_tied_velocities_are_an_error() {
    let d = drive();
    let q = DriveCoordinates {
        x: 0.0,
        y: 0.0,
        theta: 0.3,
        left: 0.0,
        right: 0.0,
    };
    let one = DriveCoordinates {
        theta: Some(1.0),
        ..Default::default()
    };
    assert_eq!(
        d.state_from_known_velocities(q, one),
        Err(KnownVelocitiesError::TooFew {
            known: 1,
            needed: 2
        })
    );
    // ẋ and ẏ are tied by the heading: together they fix the speed only
    let tied = DriveCoordinates {
        x: Some(0.3f64.cos()),
        y: Some(0.3f64.sin()),
        ..Default::default()
    };
    assert_eq!(
        d.state_from_known_velocities(q, tied),
        Err(KnownVelocitiesError::TooFew {
            known: 2,
            needed: 2
        })
    );
}

#[test]
fn velocities_that_break_the_constraints_are_named() {
    let d = drive();
    let q = DriveCoordinates {
        x: 0.0,
        y: 0.0,
        theta: 0.0,
        left: 0.0,
        right: 0.0,
    };
    // heading 0: ẏ must vanish
    let known = DriveCoordinates {
        x: Some(0.5),
        y: Some(0.1),
        theta: Some(0.2),
        ..Default::default()
    };
    match d.state_from_known_velocities(q, known) {
        Err(KnownVelocitiesError::Violation(v)) => assert_eq!(v.coordinate, "y"),
        other => panic!("{other:?}"),
    }
}
