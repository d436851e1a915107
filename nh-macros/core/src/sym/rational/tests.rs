//! Tests of [`Rational`]: fixed cases, and property tests of every operation
//! against a slow reference (`num_rational::BigRational` for arithmetic,
//! Rust's correctly rounded decimal parser for `to_f64`), over random values
//! from one digit to hundreds of digits.

use super::*;

fn q(n: i128, d: i128) -> Rational {
    Rational::new(n, d).unwrap()
}

/// `n/d` from decimal strings (signs on `n`).
fn qs(n: &str, d: &str) -> Rational {
    let (neg, n) = match n.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, n),
    };
    let n = Rational::from_digits(n).unwrap();
    let n = if neg { n.checked_neg().unwrap() } else { n };
    n.checked_div(Rational::from_digits(d).unwrap()).unwrap()
}

#[test]
fn arithmetic_is_exact() {
    assert_eq!(q(1, 3).checked_add(q(1, 6)), Some(q(1, 2)));
    assert_eq!(q(2, 4), q(1, 2));
    assert_eq!(q(3, -6), q(-1, 2));
    assert_eq!(q(2, 3).checked_mul(q(9, 4)), Some(q(3, 2)));
    assert_eq!(q(2, 3).checked_powi(-2), Some(q(9, 4)));
    assert_eq!(q(6, 5).gcd(q(9, 10)), Some(q(3, 10)));
    assert!(q(1, 3) < q(1, 2));
    assert_eq!(Rational::new(1, 0), None);
    assert_eq!(Rational::ZERO.checked_recip(), None);
    assert_eq!(q(1, 2).checked_div(Rational::ZERO), None);
}

#[test]
fn past_128_bits_values_are_promoted_and_exact() {
    let min = Rational::int(i128::MIN);
    assert_eq!(min.to_string(), i128::MIN.to_string());
    assert_eq!(Rational::new(i128::MIN, 1), Some(min));
    assert_eq!(
        min.checked_neg().unwrap().to_string(),
        "170141183460469231731687303715884105728"
    );
    let big = Rational::int(-(1i128 << 126));
    let four = big.checked_mul(Rational::int(4)).unwrap();
    assert_eq!(four.to_string(), "-340282366920938463463374607431768211456");
    // and back: canonical, so equal to the small value it came from
    assert_eq!(four.checked_div(Rational::int(4)), Some(big));
    assert_eq!(
        four.checked_div(Rational::int(4)).unwrap().to_i128_parts(),
        Some((-(1i128 << 126), 1))
    );
    let ten = Rational::int(10);
    let e400 = ten.checked_powi(400).unwrap();
    assert_eq!(e400.to_string(), format!("1{}", "0".repeat(400)));
    assert_eq!(
        e400.checked_powi(-1).unwrap().to_string(),
        format!("1/1{}", "0".repeat(400))
    );
    assert!(e400 > Rational::int(i128::MAX));
    assert!(e400.checked_neg().unwrap() < Rational::int(i128::MIN));
    assert_eq!(
        Rational::int(2).checked_powi(127).unwrap().to_string(),
        "170141183460469231731687303715884105728"
    );
}

#[test]
fn sums_of_reciprocal_primes_stay_exact() {
    let primes = [
        2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53, 59, 61, 67, 71, 73, 79, 83, 89,
        97, 101, 103, 107, 109, 113,
    ];
    let mut s = Rational::ZERO;
    for p in primes {
        s = s.checked_add(q(1, p)).unwrap();
    }
    // the denominator is the primorial, 10^46 or so
    let d: num_bigint::BigInt = primes
        .iter()
        .map(|&p| num_bigint::BigInt::from(p))
        .product();
    assert_eq!(s.denom(), d);
    // and subtracting them again returns exactly to zero
    for p in primes {
        s = s.checked_sub(q(1, p)).unwrap();
    }
    assert_eq!(s, Rational::ZERO);
    assert!(s.is_zero());
}

#[test]
fn huge_powers_are_refused_before_they_are_computed() {
    let t = std::time::Instant::now();
    assert_eq!(Rational::int(2).checked_powi(1_000_000_000), None);
    assert_eq!(Rational::int(10).checked_powi(-20_000), None);
    assert_eq!(q(3, 7).checked_powi(i64::MAX), None);
    assert!(t.elapsed().as_secs_f64() < 0.1);
    // the trivial bases take any exponent
    assert_eq!(Rational::ONE.checked_powi(i64::MAX), Some(Rational::ONE));
    assert_eq!(
        Rational::MINUS_ONE.checked_powi(i64::MAX),
        Some(Rational::MINUS_ONE)
    );
    assert_eq!(Rational::ZERO.checked_powi(i64::MAX), Some(Rational::ZERO));
    assert_eq!(Rational::ZERO.checked_powi(-1), None);
    // the limit itself is allowed
    assert!(
        Rational::int(10)
            .checked_powi(i64::from(Rational::MAX_DIGITS))
            .is_some()
    );
}

/// Expected `to_f64` of exact values, computed with Python's
/// `float(fractions.Fraction(n, d))` (correctly rounded); `None` is overflow.
const PYTHON_F64: &[(&str, &str, Option<u64>)] = &[
    (
        "662607015",
        "1000000000000000000000000000000000000000000",
        Some(0x390b860bde023111),
    ),
    ("602214076000000000000000", "1", Some(0x44dfe185ca57c517)),
    ("1", "3", Some(0x3fd5555555555555)),
    (
        "1000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000",
        "1",
        Some(0x7e37e43c8800759c),
    ),
    (
        "1",
        "1000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000",
        Some(0x01a56e1fc2f8f359),
    ),
    (
        "1",
        "100000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000",
        Some(0x00000000000007e8),
    ),
    (
        "3",
        "404804506614621236704990693437834614099113299528284236713802716054860679135990693783920767402874248990374155728633623822779617474771586953734026799881477019843034848553132722728933815484186432682479535356945490137124014966849385397236206711298319112681620113024717539104666829230461005064372655017292012526615415482186989568",
        Some(0x0000000000000002),
    ),
    (
        "179769313486231580793728971405303415079934132710037826936173778980444968292764750946649017977587207096330286416692887910946555547851940402630657488671505820681908902000708383676273854845817711531764475730270069855571366959622842914819860834936475292719074168444365510704342711559699508093042880177904174497792",
        "1",
        None,
    ),
    (
        "179769313486231580793728971405303415079934132710037826936173778980444968292764750946649017977587207096330286416692887910946555547851940402630657488671505820681908902000708383676273854845817711531764475730270069855571366959622842914819860834936475292719074168444365510704342711559699508093042880177904174497791",
        "1",
        Some(0x7fefffffffffffff),
    ),
    (
        "179769313486231570814527423731704356798070567525844996598917476803157260780028538760589558632766878171540458953514382464234321326889464182768467546703537516986049910576551282076245490090389328944075868508455133942304583236903222948165808559332123348274797826204144723168738177180919299881250404026184124858368",
        "1",
        Some(0x7fefffffffffffff),
    ),
    (
        "1",
        "404804506614621236704990693437834614099113299528284236713802716054860679135990693783920767402874248990374155728633623822779617474771586953734026799881477019843034848553132722728933815484186432682479535356945490137124014966849385397236206711298319112681620113024717539104666829230461005064372655017292012526615415482186989568",
        Some(0x0000000000000000),
    ),
    (
        "10000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000001",
        "4048045066146212367049906934378346140991132995282842367138027160548606791359906937839207674028742489903741557286336238227796174747715869537340267998814770198430348485531327227289338154841864326824795353569454901371240149668493853972362067112983191126816201130247175391046668292304610050643726550172920125266154154821869895680000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000",
        Some(0x0000000000000001),
    ),
    (
        "123456789012345678901234567890123456789",
        "987654321098765432109876543210",
        Some(0x419dcd64fb71999a),
    ),
    (
        "-7",
        "1000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000",
        Some(0x8000000000000000),
    ),
    (
        "-98765432109876543210987654321098765432109876543210",
        "3",
        Some(0xca3686a90c8b66d6),
    ),
    ("9007199254740993", "1", Some(0x4340000000000000)),
    (
        "170141183460469231731687303715884105727",
        "3",
        Some(0x47c5555555555555),
    ),
    (
        "1",
        "170141183460469231731687303715884105727",
        Some(0x3800000000000000),
    ),
];

#[test]
fn to_f64_matches_python_fractions() {
    for &(n, d, bits) in PYTHON_F64 {
        let v = qs(n, d).to_f64();
        match bits {
            Some(b) => assert_eq!(v.to_bits(), b, "{n}/{d}: {v:e}"),
            None => assert_eq!(v, f64::INFINITY, "{n}/{d}"),
        }
    }
}

#[test]
fn digits_literals_and_scientific_form() {
    assert_eq!(Rational::from_digits(""), None);
    assert_eq!(Rational::from_digits("12a"), None);
    let forty = "1234567890123456789012345678901234567890";
    assert_eq!(Rational::from_digits(forty).unwrap().to_string(), forty);
    assert_eq!(
        qs("662607015", &format!("1{}", "0".repeat(42))).sci(),
        "6.6261e-34"
    );
    assert_eq!(
        Rational::int(10).checked_powi(400).unwrap().sci(),
        "1.0000e400"
    );
    assert_eq!(
        Rational::int(-3)
            .checked_mul(Rational::int(10).checked_powi(-400).unwrap())
            .unwrap()
            .sci(),
        "-3.0000e-400"
    );
    assert_eq!(q(7, 2).floor(), Rational::int(3));
    assert_eq!(q(-7, 2).floor(), Rational::int(-4));
    let big = Rational::int(10).checked_powi(50).unwrap();
    assert_eq!(big.checked_add(q(1, 2)).unwrap().floor(), big);
    assert_eq!(
        big.checked_neg()
            .unwrap()
            .checked_sub(q(1, 2))
            .unwrap()
            .floor(),
        big.checked_neg()
            .unwrap()
            .checked_sub(Rational::ONE)
            .unwrap()
    );
    assert_eq!(Rational::from_f64(0.1).unwrap().to_f64(), 0.1);
    assert_eq!(Rational::from_f64(f64::NAN), None);
}

// ---------------------------------------------------------------- properties

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n.max(1)
    }
    fn digits(&mut self, len: usize) -> String {
        let mut s = String::with_capacity(len);
        s.push(char::from(b'1' + self.below(9) as u8));
        for _ in 1..len {
            s.push(char::from(b'0' + self.below(10) as u8));
        }
        s
    }
    /// A random value: often small, sometimes near the 128-bit boundary,
    /// sometimes hundreds of digits.
    fn value(&mut self) -> BigRational {
        let len = |r: &mut Rng| -> usize {
            match r.below(4) {
                0 => 1 + r.below(3) as usize,
                1 => 1 + r.below(19) as usize,
                2 => 35 + r.below(8) as usize,
                _ => 1 + r.below(300) as usize,
            }
        };
        let (ln, ld) = (len(self), len(self));
        let n = BigInt::parse_bytes(self.digits(ln).as_bytes(), 10).unwrap();
        let d = if self.below(3) == 0 {
            BigInt::from(1)
        } else {
            BigInt::parse_bytes(self.digits(ld).as_bytes(), 10).unwrap()
        };
        let n = if self.below(2) == 0 { -n } else { n };
        if self.below(10) == 0 {
            return BigRational::zero();
        }
        BigRational::new(n, d)
    }
}

/// The reference conversion: the decimal expansion to 1100 places (past
/// every rounding boundary of `f64`, whose midpoints need at most 1075),
/// with a sticky digit if inexact, through Rust's correctly rounded parser.
fn reference_f64(v: &BigRational) -> f64 {
    let neg = v.is_negative();
    let a = v.abs();
    let scale = num_traits::pow(BigInt::from(10), 1100);
    let (w, r) = (a.numer() * &scale).div_rem(a.denom());
    let mut s = w.to_string();
    if s.len() <= 1100 {
        s = format!("{}{s}", "0".repeat(1101 - s.len()));
    }
    let (ip, fp) = s.split_at(s.len() - 1100);
    let text = format!(
        "{}{ip}.{fp}{}",
        if neg { "-" } else { "" },
        if r.is_zero() { "" } else { "1" }
    );
    text.parse::<f64>().unwrap()
}

#[test]
fn operations_agree_with_big_rationals() {
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    for _ in 0..3000 {
        let (a, b) = (rng.value(), rng.value());
        let (x, y) = (Rational::from_big(a.clone()), Rational::from_big(b.clone()));
        // canonical: small exactly when both parts fit an i128
        let fits = |v: &BigRational| {
            v.numer().to_i128().is_some_and(|n| n != i128::MIN) && v.denom().to_i128().is_some()
        };
        assert_eq!(x.to_i128_parts().is_some(), fits(&a));
        assert_eq!(x.to_big(), a);
        assert_eq!(x.to_string(), a.to_string());
        assert_eq!(x.checked_add(y).unwrap().to_big(), &a + &b);
        assert_eq!(x.checked_sub(y).unwrap().to_big(), &a - &b);
        assert_eq!(x.checked_mul(y).unwrap().to_big(), &a * &b);
        match x.checked_div(y) {
            Some(r) => assert_eq!(r.to_big(), &a / &b),
            None => assert!(b.is_zero()),
        }
        assert_eq!(x.cmp(&y), a.cmp(&b), "{a} vs {b}");
        assert_eq!(x == y, a == b);
        assert_eq!(x.is_negative(), a.is_negative());
        assert_eq!(x.is_integer(), a.is_integer());
        assert_eq!(x.floor().to_big(), a.floor());
        assert_eq!(x.abs().to_big(), a.abs());
        let g = x.gcd(y).unwrap().to_big();
        let want = BigRational::new(a.numer().gcd(b.numer()), a.denom().lcm(b.denom()));
        assert_eq!(g, want);
        // results built two ways are one value (interned once)
        let s1 = x.checked_add(y).unwrap();
        let s2 = y.checked_add(x).unwrap();
        assert_eq!(s1, s2);
        let mut h1 = std::collections::hash_map::DefaultHasher::new();
        let mut h2 = std::collections::hash_map::DefaultHasher::new();
        std::hash::Hash::hash(&s1, &mut h1);
        std::hash::Hash::hash(&s2, &mut h2);
        assert_eq!(
            std::hash::Hasher::finish(&h1),
            std::hash::Hasher::finish(&h2)
        );
        // a round trip through a big value returns the small form
        let back = x.checked_mul(y).unwrap().checked_div(y);
        if !b.is_zero() {
            assert_eq!(back, Some(x));
        }
        let e = rng.below(9) as i64 - 4;
        match x.checked_powi(e) {
            Some(p) => assert_eq!(p.to_big(), num_traits::Pow::pow(&a, e as i32)),
            None => assert!(a.is_zero() && e < 0),
        }
    }
}

#[test]
fn to_f64_is_correctly_rounded() {
    let mut rng = Rng(0x0123_4567_89AB_CDEF);
    for _ in 0..1500 {
        let a = rng.value();
        let x = Rational::from_big(a.clone());
        let want = reference_f64(&a);
        assert_eq!(x.to_f64().to_bits(), want.to_bits(), "{a}");
    }
    // values across the whole exponent range, and the midpoints between
    // neighbouring f64s (ties to even), including subnormals and overflow
    for _ in 0..1500 {
        let bits = rng.next() & 0x7FFF_FFFF_FFFF_FFFF;
        let x = f64::from_bits(bits);
        if !x.is_finite() {
            continue;
        }
        let up = f64::from_bits(bits + 1);
        let ex = Rational::from_f64(x).unwrap();
        assert_eq!(ex.to_f64(), x);
        let top = if up.is_finite() {
            Rational::from_f64(up).unwrap()
        } else {
            // the would-be next value, 2^1024
            Rational::int(2).checked_powi(1024).unwrap()
        };
        let mid = ex
            .checked_add(top)
            .unwrap()
            .checked_div(Rational::int(2))
            .unwrap();
        let even = if bits & 1 == 0 { x } else { up };
        assert_eq!(
            mid.to_f64().to_bits(),
            even.to_bits(),
            "tie between {x:e} and {up:e}"
        );
        let tiny = top
            .checked_sub(ex)
            .unwrap()
            .checked_div(Rational::int(1 << 20))
            .unwrap();
        assert_eq!(mid.checked_sub(tiny).unwrap().to_f64(), x);
        assert_eq!(
            mid.checked_add(tiny).unwrap().to_f64().to_bits(),
            up.to_bits()
        );
        assert_eq!(mid.checked_neg().unwrap().to_f64(), -even);
    }
}
