//! The synthetic systems the size tests (`tests/scale.rs`) and the scaling
//! table (`examples/scaling.rs`) expand: one definition for both.

/// The dense family: n coordinates q1..qn, p = n/3 dense constraints
/// `dot(s_a) = Σ_α sin(q_α + s_a)/c dot(q_α)`, a dense mass matrix with
/// entries cos(q_i − q_j)/c, with the given `outputs` (may be empty).
pub fn dense(n: usize, outputs: &str) -> String {
    let (p, q) = (n / 3, (1..=n).map(|i| format!("q{i}")).collect::<Vec<_>>());
    let k = n - p;
    let mut terms = Vec::new();
    for i in 0..n {
        terms.push(format!("({}/10)*dot({})^2/2", 20 + i, q[i]));
        for j in (i + 1)..n {
            let c = (i + j + 2) * 2;
            terms.push(format!(
                "cos({} - {})*dot({})*dot({})/{c}",
                q[i], q[j], q[i], q[j]
            ));
        }
        terms.push(format!("g*cos({})/{}", q[i], i + 1));
    }
    let constraints: Vec<String> = (0..p)
        .map(|a| {
            let s = &q[k + a];
            let rhs: Vec<String> = (0..k)
                .map(|al| format!("sin({} + {s})/{}*dot({})", q[al], a + al + 2, q[al]))
                .collect();
            format!("dot({s}) = {};", rhs.join(" + "))
        })
        .collect();
    let outputs = if outputs.is_empty() {
        String::new()
    } else {
        format!("outputs {{ {outputs} }}")
    };
    format!(
        "pub struct Synth{n} {{ parameters {{ g }} coordinates {{ {} }} lagrangian = {}; constraints {{ {} }} {outputs} }}",
        q.join(", "),
        terms.join(" + "),
        constraints.join(" ")
    )
}

/// `let a{i+1} = a{i} + sin(a{i})/2;` n times; L uses only the last.
pub fn chain(n: usize) -> String {
    let lets: String = (0..n)
        .map(|i| format!("let a{} = a{i} + sin(a{i})/2; ", i + 1))
        .collect();
    format!(
        "pub struct Chain{n} {{ parameters {{ g }} coordinates {{ x, y }} let a0 = x; {lets}lagrangian = dot(a{n})^2/2 + dot(y)^2/2 - g*a{n}*y; }}"
    )
}
