//! Robustness of the macro's entry point: ≥ 10,000 random mutations of valid
//! systems (token deletion, duplication, swap, random identifiers and
//! literals, deep nesting up to thousands of levels, very long sums, numbers
//! changed to random exact values: literals of up to hundreds of digits,
//! decimal exponents up to ±400 and beyond the limit, constant powers, sums
//! of many distinct fractions; chains of up to 40 `let`s composed with sin,
//! affine maps or squares). The
//! expansion never panics, never overflows the stack, and every error it
//! reports points inside the input. Run with `--nocapture` for the figures.
mod tokens;

use proc_macro2::{Span, TokenStream, TokenTree};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::time::Instant;
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
        constraints { dot(y) = tan(theta)*dot(x); }
        forces { x: push*cos(theta) - c*dot(x); y: push*sin(theta) - c*dot(y); theta: steer; }
        outputs { routes, energy, multipliers, constraint_matrix, mass_matrix }
    }"#,
    r#"
    struct Shaken {
        parameters { m, k, c, A, omega }
        coordinates { x }
        inputs { F }
        let X = x + A*sin(omega*t);
        lagrangian = m/2*dot(X)^2 - k/2*x^2 + exp(x/3) - ln(2 + x^2) + sqrt(1 + x^2) + pi*x^(3/2);
        forces { x: -c*dot(x) + F*cos(pi*t); }
    }"#,
    r#"
    pub struct Random04 {
        parameters { k1, k2 }
        coordinates { q1, q2, q3 }
        lagrangian = -k2*q1^2*cos(q2) - 2*q1*q2/5 + dot(q1)^2*(q1^4/4 + 3/2) + dot(q1)*dot(q3)*cos(q2)*cos(q3)/2 + dot(q2)^2*(k1*cos(q1)^2/2 + 2) - 2*dot(q2)*dot(q3)*cos(q1)/5 + dot(q3)^2*(q1^2/2 + 3/2);
        constraints { dot(q3) = 3*q2^2/2*dot(q1) - cos(q1)/2*dot(q2); }
        outputs { curvature, routes }
    }"#,
    r#"
    /// The snakeboard on a belt, in generalized speeds.
    pub struct SnakeboardSpeeds {
        parameters { m, J, Jr, Jw, l, c, b }
        coordinates { x, y, theta, psi, phi }
        inputs { tau_psi, tau_phi }
        lagrangian = m*(dot(x)^2 + dot(y)^2)/2 + J*dot(theta)^2/2 + Jr*(dot(theta) + dot(psi))^2/2
            + Jw*(dot(theta) + dot(phi))^2/2 + Jw*(dot(theta) - dot(phi))^2/2;
        forces { x: -c*dot(x); psi: tau_psi; phi: tau_phi; }
        speeds { xi, w_psi, w_phi }
        kinematics {
            dot(x) = xi*cos(theta) + b*t;
            dot(y) = xi*sin(theta);
            dot(theta) = xi*tan(phi)/l;
            dot(psi) = w_psi;
            dot(phi) = w_phi;
        }
        outputs { energy, mass_matrix, reaction_forces, jacobian, linearization }
    }"#,
];

const WORDS: &[&str] = &[
    "x",
    "y",
    "theta",
    "m",
    "R",
    "dot",
    "sin",
    "cos",
    "tan",
    "exp",
    "ln",
    "sqrt",
    "pi",
    "t",
    "let",
    "lagrangian",
    "constraints",
    "speeds",
    "kinematics",
    "reaction_forces",
    "coordinates",
    "parameters",
    "inputs",
    "forces",
    "outputs",
    "struct",
    "pub",
    "fn",
    "self",
    "r#type",
    "energy",
    "jacobian",
    "routes",
    "zz_unknown",
    "X",
    "_",
    "+",
    "-",
    "*",
    "/",
    "^",
    "=",
    ";",
    ",",
    ":",
    "!",
    "&",
    "#",
    "0",
    "1",
    "2.5",
    "0.0",
    "1e308",
    "1e-400",
    "99999999999999999999999999999999999999999",
    "0.000000000000000000000000000000000000001",
    "7u8",
    "3.0f32",
    "\"str\"",
    "'c'",
];

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

fn mutate(rng: &mut Rng, toks: &mut Vec<String>) -> &'static str {
    let n = toks.len();
    match rng.below(10) {
        0 => {
            toks.remove(rng.below(n));
            "delete"
        }
        1 => {
            let i = rng.below(n);
            let t = toks[i].clone();
            toks.insert(i, t);
            "duplicate"
        }
        2 => {
            let (i, j) = (rng.below(n), rng.below(n));
            toks.swap(i, j);
            "swap"
        }
        3 | 4 => {
            let i = rng.below(n);
            toks[i] = WORDS[rng.below(WORDS.len())].to_string();
            "replace"
        }
        5 => {
            let i = rng.below(n);
            toks.insert(i, WORDS[rng.below(WORDS.len())].to_string());
            "insert"
        }
        6 => {
            // deep nesting around a token: up to a few thousand levels
            let depth = 1 + rng.below(3000);
            let i = rng.below(n);
            if toks[i].len() > 1000 {
                return "skipped";
            }
            let (open, close) = match rng.below(3) {
                0 => ("(", ")"),
                1 => ("sin(", ")"),
                _ => ("-(", ")"),
            };
            let wrapped = format!("{}{}{}", open.repeat(depth), toks[i], close.repeat(depth));
            toks[i] = wrapped;
            "deep nesting"
        }
        7 => {
            // a very long sum or product, or a tower of powers
            let len = 1 + rng.below(5_000);
            let op = ["+", "*", "^", "-"][rng.below(4)];
            let i = rng.below(n);
            if toks[i].len() > 50 {
                return "skipped";
            }
            let chain = vec![toks[i].clone(); len].join(&format!(" {op} "));
            toks[i] = chain;
            "long chain"
        }
        9 => {
            // a number of the input (or any token) becomes a random exact value
            // (not exponents: a velocity to a power of 20-odd with a
            // 30-digit denominator is expression swell of the derivation,
            // not a matter of numbers; constant powers come from
            // `random_number` itself)
            let nums: Vec<usize> = (0..n)
                .filter(|&i| toks[i].starts_with(|c: char| c.is_ascii_digit()))
                .filter(|&i| i == 0 || toks[i - 1] != "^")
                .collect();
            let i = if nums.is_empty() || rng.below(4) == 0 {
                rng.below(n)
            } else {
                nums[rng.below(nums.len())]
            };
            if i > 0 && toks[i - 1] == "^" {
                return "skipped";
            }
            toks[i] = random_number(rng);
            "number"
        }
        _ if rng.below(16) == 0 => {
            // a long chain of `let`s (sin-chained or affine), used by the
            // Lagrangian: swell by composition
            let Some(at) = toks.iter().position(|t| t == "lagrangian") else {
                return "skipped";
            };
            let len = 1 + rng.below(40);
            let step = ["+ sin(__fz{k})/2", "* 2 + 1/3", "* __fz{k} / 7"][rng.below(3)];
            let mut chain = String::from("let __fz0 = x;");
            for k in 0..len {
                let next = step.replace("{k}", &k.to_string());
                chain.push_str(&format!(" let __fz{} = __fz{k} {next};", k + 1));
            }
            toks.insert(at, chain);
            let uses: Vec<usize> = (at + 1..toks.len())
                .filter(|&i| toks[i] == "x" || toks[i] == "theta")
                .collect();
            if let Some(&u) = uses.get(rng.below(uses.len().max(1))) {
                toks[u] = format!("__fz{len}");
            }
            "let chain"
        }
        _ => {
            let i = rng.below(n);
            let lit = ["0", "1/0", "0^0", "x^1000000", "2^-1", "1e-300", "(x - x)"][rng.below(7)];
            toks[i] = lit.to_string();
            "literal"
        }
    }
}

fn digits(rng: &mut Rng, len: usize) -> String {
    let mut s = String::with_capacity(len);
    s.push(char::from(b'1' + rng.below(9) as u8));
    for _ in 1..len {
        s.push(char::from(b'0' + rng.below(10) as u8));
    }
    s
}

/// A random number expression: exact literals of up to hundreds of digits,
/// decimals with exponents (some beyond the supported ±10000), constant
/// powers (some too large to compute), sums of many distinct fractions, and
/// values that leave or underflow the range of `f64`.
fn random_number(rng: &mut Rng) -> String {
    match rng.below(8) {
        0 => {
            let len = 1 + rng.below(300);
            digits(rng, len)
        }
        1 => {
            let (a, b) = (1 + rng.below(20), 1 + rng.below(20));
            let e = rng.below(801) as i64 - 400;
            format!("{}.{}e{e}", digits(rng, a), digits(rng, b))
        }
        2 => [
            "1e300",
            "1e-300",
            "1e308",
            "1e-320",
            "6.62607015e-34",
            "6.02214076e23",
            "1e20000",
            "2e-10001",
        ][rng.below(8)]
        .to_string(),
        3 => {
            let base = [
                "2",
                "10",
                "(3/7)",
                "(-5)",
                "1.5",
                "(10^20 + 1)",
                "(-1)",
                "0",
            ][rng.below(8)];
            let e = [
                "127",
                "400",
                "-45",
                "(1/3)",
                "(10^9)",
                "1000",
                "(-1)",
                "(7/2)",
                "(10^30 + 1/2)",
            ][rng.below(9)];
            format!("{base}^{e}")
        }
        4 => {
            // many distinct denominators: their common multiple grows large
            let k = 2 + rng.below(60);
            let start = 2 + rng.below(200);
            let terms: Vec<String> = (start..start + k)
                .map(|d| format!("{}/{d}", 1 + rng.below(97)))
                .collect();
            format!("({})", terms.join(" + "))
        }
        5 => {
            let (a, b) = (1 + rng.below(200), 1 + rng.below(200));
            format!("({}/{})", digits(rng, a), digits(rng, b))
        }
        6 => [
            "sqrt(0)",
            "sqrt(-1)",
            "ln(0)",
            "ln(-2)",
            "(-8)^(1/3)",
            "tan(pi/2)",
            "1/sqrt(0)",
            "0^(-1)",
            "10^400",
            "10^-400",
        ][rng.below(10)]
        .to_string(),
        _ => {
            let len = 1 + rng.below(40);
            format!("{}.{}", digits(rng, len), digits(rng, len))
        }
    }
}

/// Spans of every `compile_error!` invocation in an expansion.
fn error_spans(ts: &TokenStream, out: &mut Vec<Span>) {
    let toks: Vec<TokenTree> = ts.clone().into_iter().collect();
    for (i, tt) in toks.iter().enumerate() {
        match tt {
            TokenTree::Ident(id) if id == "compile_error" => {
                out.push(id.span());
                if let Some(TokenTree::Group(g)) = toks.get(i + 2) {
                    out.push(g.span());
                }
            }
            TokenTree::Group(g) => error_spans(&g.stream(), out),
            _ => {}
        }
    }
}

#[test]
fn random_mutations_never_panic_and_errors_point_inside_the_input() {
    // rustc runs proc macros on a thread with an 8 MiB stack; so does this test
    let handle = std::thread::Builder::new()
        .stack_size(8 << 20)
        .spawn(run_fuzz)
        .expect("spawn the fuzz thread");
    handle
        .join()
        .expect("the fuzz thread panicked or overflowed");
}

fn run_fuzz() {
    let start = Instant::now();
    let mut rng = Rng(0x005E_ED0F_F022_u64);
    let (mut cases, mut lexed, mut errors, mut clean) = (0usize, 0usize, 0usize, 0usize);
    let mut by_kind: std::collections::BTreeMap<&str, usize> = Default::default();
    let seeds: Vec<Vec<String>> = SEEDS
        .iter()
        .map(|s| {
            let mut v = Vec::new();
            flatten(s.parse().expect("seed parses"), &mut v);
            v
        })
        .collect();
    while lexed < 10_000 {
        cases += 1;
        let mut toks = seeds[rng.below(seeds.len())].clone();
        let rounds = 1 + rng.below(4);
        let mut kinds = Vec::new();
        for _ in 0..rounds {
            if toks.is_empty() {
                break;
            }
            kinds.push(mutate(&mut rng, &mut toks));
        }
        let text = toks.join(" ");
        // what rustc's lexer rejects (unbalanced delimiters, bad literals) never reaches a macro
        let Ok(input) = text.parse::<TokenStream>() else {
            continue;
        };
        lexed += 1;
        for k in &kinds {
            *by_kind.entry(k).or_default() += 1;
        }
        if std::env::var("FUZZ_DUMP")
            .ok()
            .and_then(|v| v.parse::<usize>().ok())
            == Some(cases)
        {
            std::fs::write("/tmp/fuzz_case.txt", &text).expect("write the case");
        }
        if std::env::var_os("FUZZ_TRACE").is_some() {
            eprintln!("case {cases} {kinds:?}: {}", &text[..text.len().min(300)]);
        }
        let (lo, hi) = extent(&input);
        let t0 = Instant::now();
        let result = catch_unwind(AssertUnwindSafe(|| nh_core::expand(input.clone())));
        let dt = t0.elapsed().as_secs_f64();
        if std::env::var_os("FUZZ_SLOW").is_some() && dt > 0.05 {
            eprintln!(
                "slow case {cases} ({dt:.2} s) {kinds:?}: {}",
                &text[..text.len().min(400)]
            );
        }
        let out = match result {
            Ok(out) => out,
            Err(_) => panic!("the expansion panicked on input ({kinds:?}):\n{text}"),
        };
        let mut spans = Vec::new();
        error_spans(&out, &mut spans);
        if spans.is_empty() {
            clean += 1;
        } else {
            errors += 1;
        }
        for s in spans {
            let r = s.byte_range();
            assert!(
                r.start >= lo && r.end <= hi && r.start < r.end,
                "an error points outside the input ({}..{} not in {lo}..{hi}), mutations {kinds:?}:\n{}\n---\n{out}",
                r.start,
                r.end,
                &text[..text.len().min(2000)]
            );
        }
    }
    let secs = start.elapsed().as_secs_f64();
    println!(
        "{cases} mutated inputs, {lexed} lexed and expanded ({errors} with errors, {clean} cleanly) in {secs:.1} s; mutations applied: {by_kind:?}"
    );
    assert!(
        errors > 1_000 && clean > 100,
        "the mutations must exercise both outcomes"
    );
}
