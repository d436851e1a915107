//! Numbers are exact rationals of any size: a physicist's literals
//! (`6.62607015e-34`, `6.02214076e23`, `1e300`, forty-digit integers), large
//! powers and sums of many distinct fractions compile, and the constants the
//! generated code holds are the exact values correctly rounded to `f64`.
use nonholonomic::prelude::*;

/// `ẍ` of a one-coordinate system at `x = x0`, `ẋ = 0`, `t = 0`.
macro_rules! acc {
    ($s:expr, $x:expr) => {
        $s.accelerations(0.0, &SVector::from([$x]), &SVector::from([0.0]))[0]
    };
}

// Each system is a unit mass in a linear potential: ẍ = −∂V/∂x is the
// constant written in the Lagrangian, exactly as the literal denotes it.
nonholonomic_system! { struct Planck { coordinates { x } lagrangian = dot(x)^2/2 + 6.62607015e-34*x; } }
nonholonomic_system! { struct Avogadro { coordinates { x } lagrangian = dot(x)^2/2 + 6.02214076e23*x; } }
nonholonomic_system! { struct Huge { coordinates { x } lagrangian = dot(x)^2/2 + 1e300*x; } }
nonholonomic_system! { struct Tiny { coordinates { x } lagrangian = dot(x)^2/2 + 1e-300*x; } }
nonholonomic_system! { struct Subnormal { coordinates { x } lagrangian = dot(x)^2/2 + 1e-310*x; } }
nonholonomic_system! { struct Vanishing { coordinates { x } lagrangian = dot(x)^2/2 + 1e-400*x; } }
nonholonomic_system! { struct FortyDigits { coordinates { x } lagrangian = dot(x)^2/2 + 1234567890123456789012345678901234567890*x; } }
nonholonomic_system! { struct TwoTo127 { coordinates { x } lagrangian = dot(x)^2/2 + 2^127*x; } }
nonholonomic_system! { struct Cancelled { coordinates { x } lagrangian = dot(x)^2/2 + 10^400/10^399*x; } }
nonholonomic_system! { struct HeavyMass { coordinates { x } lagrangian = 1e200*dot(x)^2/2 + 3e200*x; } }
nonholonomic_system! { struct ZeroRoot { coordinates { x } lagrangian = dot(x)^2/2 + (sqrt(0) + 0^(1/3) + 2)*x; } }
nonholonomic_system! {
    struct ReciprocalPrimes {
        coordinates { x }
        lagrangian = dot(x)^2/2 + (1/2 + 1/3 + 1/5 + 1/7 + 1/11 + 1/13 + 1/17 + 1/19 + 1/23 + 1/29 + 1/31 + 1/37 + 1/41 + 1/43 + 1/47 + 1/53 + 1/59 + 1/61 + 1/67 + 1/71 + 1/73 + 1/79 + 1/83 + 1/89 + 1/97 + 1/101 + 1/103 + 1/107 + 1/109 + 1/113)*x;
    }
}

#[test]
fn literals_are_exact_and_correctly_rounded() {
    // Rust's float literals are correctly rounded: the same values exactly
    assert_eq!(acc!(Planck::new(), 0.0), 6.62607015e-34);
    assert_eq!(acc!(Avogadro::new(), 0.0), 6.02214076e23);
    assert_eq!(acc!(Huge::new(), 0.0), 1e300);
    assert_eq!(acc!(Tiny::new(), 0.0), 1e-300);
    assert_eq!(acc!(Subnormal::new(), 0.0), 1e-310);
    assert_eq!(acc!(Vanishing::new(), 0.0), 0.0);
    assert_eq!(
        acc!(FortyDigits::new(), 0.0),
        1234567890123456789012345678901234567890.0
    );
    assert_eq!(acc!(TwoTo127::new(), 0.0), 2f64.powi(127));
    assert_eq!(acc!(Cancelled::new(), 0.0), 10.0);
    assert_eq!(acc!(HeavyMass::new(), 0.0), 3.0);
    assert_eq!(acc!(ZeroRoot::new(), 0.0), 2.0);
    // Σ 1/p over the first 30 primes (a denominator of 155 bits), rounded
    // by Python's fractions.Fraction
    assert_eq!(acc!(ReciprocalPrimes::new(), 0.0), 1.8497965928532112);
}

nonholonomic_system! {
    /// The adversarial case of issue 10: 44 cosines with distinct
    /// denominators 47..90, whose common content overflowed 128 bits.
    struct Cosines {
        parameters { g }
        coordinates { x }
        lagrangian = dot(x)^2/2 - g*(cos(46*x)/47 + cos(47*x)/48 + cos(48*x)/49 + cos(49*x)/50
            + cos(50*x)/51 + cos(51*x)/52 + cos(52*x)/53 + cos(53*x)/54 + cos(54*x)/55
            + cos(55*x)/56 + cos(56*x)/57 + cos(57*x)/58 + cos(58*x)/59 + cos(59*x)/60
            + cos(60*x)/61 + cos(61*x)/62 + cos(62*x)/63 + cos(63*x)/64 + cos(64*x)/65
            + cos(65*x)/66 + cos(66*x)/67 + cos(67*x)/68 + cos(68*x)/69 + cos(69*x)/70
            + cos(70*x)/71 + cos(71*x)/72 + cos(72*x)/73 + cos(73*x)/74 + cos(74*x)/75
            + cos(75*x)/76 + cos(76*x)/77 + cos(77*x)/78 + cos(78*x)/79 + cos(79*x)/80
            + cos(80*x)/81 + cos(81*x)/82 + cos(82*x)/83 + cos(83*x)/84 + cos(84*x)/85
            + cos(85*x)/86 + cos(86*x)/87 + cos(87*x)/88 + cos(88*x)/89 + cos(89*x)/90);
    }
}

#[test]
fn many_distinct_fractions_compile_and_give_the_right_acceleration() {
    let g = 9.81;
    let s = Cosines::new(g);
    for &x in &[0.0, 0.013, 0.4, -1.7, 2.9] {
        // ẍ = −∂V/∂x with V = g Σ cos(k x)/(k + 1)
        let expect: f64 = (46..=89)
            .map(|k| {
                let k = f64::from(k);
                g * k / (k + 1.0) * (k * x).sin()
            })
            .sum();
        let a = acc!(s, x);
        assert!(
            (a - expect).abs() <= 1e-12 * g * 44.0,
            "x = {x}: {a} vs {expect}"
        );
    }
}
