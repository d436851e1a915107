//! The coefficients of the Rosenbrock–Wanner methods RODAS4 and Rodas5P, in
//! the form the one stepping code in `rosenbrock.rs` runs.
// The coefficients are kept digit for digit as published.
#![allow(clippy::excessive_precision)]

use crate::method::Pi;

/// A stiffly accurate Rosenbrock–Wanner method with `S` stages in Hairer's
/// transformed formulation (Hairer & Wanner, *Solving ODEs II*, IV.7,
/// (7.25)): with `W = I/(hγ) − J`,
///
/// ```text
/// W U_i = f(t + α_i h, x + Σ_{j<i} a_ij U_j) + Σ_{j<i} (c_ij/h) U_j + h γ_i ∂f/∂t,
/// x_new = x + Σ_{j<S} a_Sj U_j + U_S,   error estimate U_S,
/// ```
///
/// the embedded solution `x + Σ_{j<S} a_Sj U_j` being the argument of the
/// last stage. From stage `chain` on, every stage is evaluated at `t + h`
/// and its argument is the previous stage's argument plus the previous
/// stage (`a_ij = a_{i−1,j} + δ_{i−1,j}`), which the stepping code uses.
/// Dense output: `x(θ) = (1−θ) x + θ (x_new + (1−θ)(k_1 + θ (k_2 + θ k_3)))`
/// with `k_r = Σ_i dense[r][i] U_i`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Tableau<const S: usize> {
    /// The diagonal `γ`.
    pub(crate) gamma: f64,
    /// `a_ij` (row `i`, column `j < i`).
    pub(crate) a: [[f64; S]; S],
    /// `c_ij` (row `i`, column `j < i`).
    pub(crate) c: [[f64; S]; S],
    /// The nodes `α_i = Σ_j α_ij`.
    pub(crate) alpha: [f64; S],
    /// The time-derivative weights `γ_i = Σ_j γ_ij`.
    pub(crate) gamma_row: [f64; S],
    /// The first stage whose argument is the previous argument plus the
    /// previous stage.
    pub(crate) chain: usize,
    /// The dense-output weights `k_r = Σ_i dense[r][i] U_i`.
    pub(crate) dense: [[f64; S]; 3],
}

/// A Rosenbrock method for the step driver: its tableau, order and step
/// controller.
pub(crate) trait Scheme<const S: usize> {
    /// The coefficients.
    const TABLEAU: Tableau<S>;
    /// The order of the solution (the embedded one is one lower).
    const ORDER: u32;
    /// The step-size controller.
    const PI: Pi;
}

/// The controller of Hairer's `RODAS` (`0.2 ≤ h_new/h ≤ 6`, safety 0.9,
/// Gustafsson's predictive correction) with the exponent `1/(q+1)` of an
/// embedded method of order `q`.
const fn rodas_pi(embedded_order: u32) -> Pi {
    Pi {
        safe: 0.9,
        expo: 1.0 / (embedded_order as f64 + 1.0),
        beta: 0.0,
        fac_lo: 1.0 / 6.0,
        fac_hi: 5.0,
        gustafsson: true,
    }
}

/// RODAS4: Hairer & Wanner, *Solving ODEs II*, section IV.7, table 7.2,
/// and Hairer's `rodas.f` (`METH = 1`, dense output `D21`…`D35`); order 4,
/// embedded order 3, dense output of order 3.
pub(crate) struct Rodas4Scheme;

impl Scheme<6> for Rodas4Scheme {
    const ORDER: u32 = 4;
    const PI: Pi = rodas_pi(3);
    const TABLEAU: Tableau<6> = {
        const A51: f64 = 1.221_224_509_226_641;
        const A52: f64 = 6.019_134_481_288_629;
        const A53: f64 = 12.537_083_329_320_87;
        const A54: f64 = -0.687_886_036_105_895;
        Tableau {
            gamma: 0.25,
            a: [
                [0.0; 6],
                [1.544, 0.0, 0.0, 0.0, 0.0, 0.0],
                [
                    0.946_678_528_081_582_6,
                    0.255_701_169_898_328_4,
                    0.0,
                    0.0,
                    0.0,
                    0.0,
                ],
                [
                    3.314_825_187_068_521,
                    2.896_124_015_972_201,
                    0.998_641_913_997_781_7,
                    0.0,
                    0.0,
                    0.0,
                ],
                [A51, A52, A53, A54, 0.0, 0.0],
                [A51, A52, A53, A54, 1.0, 0.0],
            ],
            c: [
                [0.0; 6],
                [-5.6688, 0.0, 0.0, 0.0, 0.0, 0.0],
                [
                    -2.430_093_356_833_875,
                    -0.206_359_915_709_191_5,
                    0.0,
                    0.0,
                    0.0,
                    0.0,
                ],
                [
                    -0.107_352_905_815_137_5,
                    -9.594_562_251_023_355,
                    -20.470_286_148_096_16,
                    0.0,
                    0.0,
                    0.0,
                ],
                [
                    7.496_443_313_967_647,
                    -10.246_804_314_643_52,
                    -33.999_903_528_199_05,
                    11.708_908_932_061_6,
                    0.0,
                    0.0,
                ],
                [
                    8.083_246_795_921_522,
                    -7.981_132_988_064_893,
                    -31.521_594_328_743_71,
                    16.319_305_431_231_36,
                    -6.058_818_238_834_054,
                    0.0,
                ],
            ],
            alpha: [0.0, 0.386, 0.21, 0.63, 1.0, 1.0],
            gamma_row: [0.25, -0.1043, 0.1035, -0.036_200_000_000_000_23, 0.0, 0.0],
            chain: 5,
            dense: [
                [
                    10.126_235_083_445_86,
                    -7.487_995_877_610_167,
                    -34.800_918_615_557_47,
                    -7.992_771_707_568_823,
                    1.025_137_723_295_662,
                    0.0,
                ],
                [
                    -0.676_280_339_280_125_3,
                    6.087_714_651_680_015,
                    16.430_843_208_924_78,
                    24.767_225_114_183_86,
                    -6.594_389_125_716_872,
                    0.0,
                ],
                [0.0; 6],
            ],
        }
    };
}

/// Rodas5P: G. Steinebach, *Construction of Rosenbrock–Wanner method
/// Rodas5P and numerical benchmarks within the Julia Differential Equations
/// package*, BIT Numerical Mathematics 63, 27 (2023); the coefficients as
/// in OrdinaryDiffEq.jl, `lib/OrdinaryDiffEqRosenbrock/src/rosenbrock_tableaus.jl`
/// (`RODAS5PA`, `RODAS5PC`, `RODAS5Pc`, `RODAS5Pd`, `RODAS5PH`). Order 5,
/// embedded order 4, dense output of order 4.
pub(crate) struct Rodas5PScheme;

impl Scheme<8> for Rodas5PScheme {
    const ORDER: u32 = 5;
    const PI: Pi = rodas_pi(4);
    const TABLEAU: Tableau<8> = {
        const A6: [f64; 5] = [
            -7.502846399306121,
            2.561846144803919,
            -11.627539656261098,
            -0.18268767659942256,
            0.030198172008377946,
        ];
        Tableau {
            gamma: 0.21193756319429014,
            a: [
                [0.0; 8],
                [3.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
                [
                    2.849394379747939,
                    0.45842242204463923,
                    0.0,
                    0.0,
                    0.0,
                    0.0,
                    0.0,
                    0.0,
                ],
                [
                    -6.954028509809101,
                    2.489845061869568,
                    -10.358996098473584,
                    0.0,
                    0.0,
                    0.0,
                    0.0,
                    0.0,
                ],
                [
                    2.8029986275628964,
                    0.5072464736228206,
                    -0.3988312541770524,
                    -0.04721187230404641,
                    0.0,
                    0.0,
                    0.0,
                    0.0,
                ],
                [A6[0], A6[1], A6[2], A6[3], A6[4], 0.0, 0.0, 0.0],
                [A6[0], A6[1], A6[2], A6[3], A6[4], 1.0, 0.0, 0.0],
                [A6[0], A6[1], A6[2], A6[3], A6[4], 1.0, 1.0, 0.0],
            ],
            c: [
                [0.0; 8],
                [-14.155112264123755, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
                [
                    -17.97296035885952,
                    -2.859693295451294,
                    0.0,
                    0.0,
                    0.0,
                    0.0,
                    0.0,
                    0.0,
                ],
                [
                    147.12150275711716,
                    -1.41221402718213,
                    71.68940251302358,
                    0.0,
                    0.0,
                    0.0,
                    0.0,
                    0.0,
                ],
                [
                    165.43517024871676,
                    -0.4592823456491126,
                    42.90938336958603,
                    -5.961986721573306,
                    0.0,
                    0.0,
                    0.0,
                    0.0,
                ],
                [
                    24.854864614690072,
                    -3.0009227002832186,
                    47.4931110020768,
                    5.5814197821558125,
                    -0.6610691825249471,
                    0.0,
                    0.0,
                    0.0,
                ],
                [
                    30.91273214028599,
                    -3.1208243349937974,
                    77.79954646070892,
                    34.28646028294783,
                    -19.097331116725623,
                    -28.087943162872662,
                    0.0,
                    0.0,
                ],
                [
                    37.80277123390563,
                    -3.2571969029072276,
                    112.26918849496327,
                    66.9347231244047,
                    -40.06618937091002,
                    -54.66780262877968,
                    -9.48861652309627,
                    0.0,
                ],
            ],
            alpha: [
                0.0,
                0.6358126895828704,
                0.4095798393397535,
                0.9769306725060716,
                0.4288403609558664,
                1.0,
                1.0,
                1.0,
            ],
            gamma_row: [
                0.21193756319429014,
                -0.42387512638858027,
                -0.3384627126235924,
                1.8046452872882734,
                2.325825639765069,
                0.0,
                0.0,
                0.0,
            ],
            chain: 6,
            dense: [
                [
                    25.948786856663858,
                    -2.5579724845846235,
                    10.433815404888879,
                    -2.3679251022685204,
                    0.524948541321073,
                    1.1241088310450404,
                    0.4272876194431874,
                    -0.17202221070155493,
                ],
                [
                    -9.91568850695171,
                    -0.9689944594115154,
                    3.0438037242978453,
                    -24.495224566215796,
                    20.176138334709044,
                    15.98066361424651,
                    -6.789040303419874,
                    -6.710236069923372,
                ],
                [
                    11.419903575922262,
                    2.8879645146136994,
                    72.92137995996029,
                    80.12511834622643,
                    -52.072871366152654,
                    -59.78993625266729,
                    -0.15582684282751913,
                    4.883087185713722,
                ],
            ],
        }
    };
}

#[cfg(test)]
mod tests {
    //! The order conditions of Rosenbrock methods (Hairer & Wanner, *Solving
    //! ODEs II*, IV.7, table 7.1): back in the untransformed form
    //! `k_i = h f(x + Σ α_ij k_j) + h J Σ γ_ij k_j`, `x_new = x + Σ b_i k_i`
    //! (`Γ = (diag(1/γ) − C)^(−1)`, `α = A Γ`, `b = m Γ` with the weights
    //! `m` of the `U_i`, (7.8)), the method has order `p` when
    //! `bᵀ Φ(t) = 1/γ(t)` for every rooted tree `t` with at most `p` nodes,
    //! where `Φ_i(τ) = 1`, a node with a single child `t'` contributes
    //! `Σ_j β_ij Φ_j(t')` with `β = α + Γ` (diagonal included) and a node with
    //! children `t_1 … t_m` (m ≥ 2) contributes `Π_k Σ_j α_ij Φ_j(t_k)`
    //! (Table 7.1 is this rule written out up to order 4).
    use super::*;

    /// A rooted tree as the list of its root's subtrees (sorted).
    #[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
    struct Tree(Vec<Tree>);

    impl Tree {
        fn order(&self) -> usize {
            1 + self.0.iter().map(Tree::order).sum::<usize>()
        }

        fn density(&self) -> f64 {
            self.order() as f64 * self.0.iter().map(Tree::density).product::<f64>()
        }
    }

    /// Every rooted tree with `n` nodes, each once.
    fn trees(n: usize) -> Vec<Tree> {
        let smaller: Vec<Tree> = (1..n).flat_map(trees).collect();
        let mut out = Vec::new();
        // The root's children: multisets of smaller trees (indices
        // non-increasing) whose orders sum to n − 1.
        fn extend(
            smaller: &[Tree],
            from: usize,
            left: usize,
            chosen: &mut Vec<Tree>,
            out: &mut Vec<Tree>,
        ) {
            if left == 0 {
                out.push(Tree(chosen.clone()));
                return;
            }
            for i in (0..from).rev() {
                if smaller[i].order() <= left {
                    chosen.push(smaller[i].clone());
                    extend(smaller, i + 1, left - smaller[i].order(), chosen, out);
                    chosen.pop();
                }
            }
        }
        extend(&smaller, smaller.len(), n - 1, &mut Vec::new(), &mut out);
        out
    }

    type Mat<const S: usize> = [[f64; S]; S];

    fn mul<const S: usize>(x: &Mat<S>, y: &Mat<S>) -> Mat<S> {
        core::array::from_fn(|i| core::array::from_fn(|j| (0..S).map(|k| x[i][k] * y[k][j]).sum()))
    }

    /// The inverse of a lower triangular matrix by forward substitution.
    #[allow(clippy::needless_range_loop)] // indices as in the formula
    fn lower_inverse<const S: usize>(l: &Mat<S>) -> Mat<S> {
        let mut inv = [[0.0; S]; S];
        for col in 0..S {
            for i in 0..S {
                let e = if i == col { 1.0 } else { 0.0 };
                let s: f64 = (0..i).map(|k| l[i][k] * inv[k][col]).sum();
                inv[i][col] = (e - s) / l[i][i];
            }
        }
        inv
    }

    /// `(α, Γ, b, b̂)` of the untransformed method.
    fn untransformed<const S: usize>(t: &Tableau<S>) -> (Mat<S>, Mat<S>, [f64; S], [f64; S]) {
        let gamma_inv: Mat<S> = core::array::from_fn(|i| {
            core::array::from_fn(|j| if i == j { 1.0 / t.gamma } else { -t.c[i][j] })
        });
        let big_gamma = lower_inverse(&gamma_inv);
        let alpha = mul(&t.a, &big_gamma);
        let mut m = t.a[S - 1];
        let embedded = (0..S).map(|j| m[j]).collect::<Vec<_>>();
        m[S - 1] = 1.0;
        let b = core::array::from_fn(|j| (0..S).map(|i| m[i] * big_gamma[i][j]).sum());
        let bh = core::array::from_fn(|j| (0..S).map(|i| embedded[i] * big_gamma[i][j]).sum());
        (alpha, big_gamma, b, bh)
    }

    /// `Φ(t)` of the method, per stage.
    fn phi<const S: usize>(t: &Tree, alpha: &Mat<S>, beta: &Mat<S>) -> [f64; S] {
        let apply = |m: &Mat<S>, v: &[f64; S]| -> [f64; S] {
            core::array::from_fn(|i| (0..S).map(|j| m[i][j] * v[j]).sum())
        };
        match t.0.as_slice() {
            [] => [1.0; S],
            [only] => apply(beta, &phi(only, alpha, beta)),
            children => {
                let mut out = [1.0; S];
                for child in children {
                    let v = apply(alpha, &phi(child, alpha, beta));
                    for (o, vi) in out.iter_mut().zip(v) {
                        *o *= vi;
                    }
                }
                out
            }
        }
    }

    /// The largest residual `|bᵀΦ(t) − 1/γ(t)|` over the trees of order
    /// `order`, for the weights `b`.
    fn residual<const S: usize>(tab: &Tableau<S>, weights: &[f64; S], order: usize) -> f64 {
        let (alpha, big_gamma, _, _) = untransformed(tab);
        let beta: Mat<S> =
            core::array::from_fn(|i| core::array::from_fn(|j| alpha[i][j] + big_gamma[i][j]));
        trees(order)
            .iter()
            .map(|t| {
                let p = phi(t, &alpha, &beta);
                let sum: f64 = (0..S).map(|i| weights[i] * p[i]).sum();
                (sum - 1.0 / t.density()).abs()
            })
            .fold(0.0, f64::max)
    }

    fn check<const S: usize>(name: &str, tab: &Tableau<S>, order: usize) {
        let (alpha, big_gamma, b, bh) = untransformed(tab);
        for i in 0..S {
            // Nodes and time weights are the row sums of α and Γ.
            let (ai, gi): (f64, f64) = (alpha[i].iter().sum(), big_gamma[i].iter().sum());
            assert!(
                (ai - tab.alpha[i]).abs() < 1e-12,
                "{name}: α_{i} {ai} vs {}",
                tab.alpha[i]
            );
            assert!((gi - tab.gamma_row[i]).abs() < 1e-12, "{name}: γ_{i} {gi}");
            assert!(
                (big_gamma[i][i] - tab.gamma).abs() < 1e-15,
                "{name}: γ_{i}{i}"
            );
        }
        // The chained stages: a_ij = a_{i−1,j} + δ_{i−1,j}, at t + h.
        for i in tab.chain..S {
            for j in 0..S {
                let step = if j == i - 1 { 1.0 } else { 0.0 };
                assert_eq!(tab.a[i][j], tab.a[i - 1][j] + step, "{name}: a[{i}][{j}]");
            }
            assert_eq!(tab.alpha[i], 1.0);
        }
        assert_eq!(trees(5).len(), 9);
        for p in 1..=order + 1 {
            let (main, emb) = (residual(tab, &b, p), residual(tab, &bh, p));
            println!("{name}: order {p}: residual {main:.1e}, embedded {emb:.1e}");
            if p <= order {
                assert!(
                    main < 1e-11,
                    "{name}: order condition of order {p}: {main:e}"
                );
            } else {
                assert!(main > 1e-6, "{name}: satisfies order {p} too");
            }
            if p < order {
                assert!(emb < 1e-11, "{name}: embedded order condition {p}: {emb:e}");
            } else {
                assert!(emb > 1e-6, "{name}: embedded satisfies order {p}: {emb:e}");
            }
        }
        // Stiffly accurate, hence L-stable: R(∞) = 1 − bᵀ B⁻¹ 1 = 0 with
        // B = α + Γ.
        let beta: Mat<S> =
            core::array::from_fn(|i| core::array::from_fn(|j| alpha[i][j] + big_gamma[i][j]));
        let beta_inv = lower_inverse(&beta);
        let r_inf = |w: &[f64; S]| {
            1.0 - (0..S)
                .map(|i| w[i] * beta_inv[i].iter().sum::<f64>())
                .sum::<f64>()
        };
        println!(
            "{name}: R(∞) = {:.1e}, embedded {:.1e}",
            r_inf(&b),
            r_inf(&bh)
        );
        assert!(r_inf(&b).abs() < 1e-12, "{name}: R(∞) = {}", r_inf(&b));
    }

    #[test]
    fn rooted_trees_are_counted_right() {
        // OEIS A000081: 1, 1, 2, 4, 9, 20.
        let counts: Vec<usize> = (1..=6).map(|n| trees(n).len()).collect();
        assert_eq!(counts, [1, 1, 2, 4, 9, 20]);
        let densities: Vec<f64> = trees(3).iter().map(Tree::density).collect();
        assert!(densities.contains(&3.0) && densities.contains(&6.0));
    }

    #[test]
    fn rodas4_satisfies_the_order_conditions_of_order_4() {
        check("RODAS4", &Rodas4Scheme::TABLEAU, 4);
    }

    #[test]
    fn rodas5p_satisfies_the_order_conditions_of_order_5() {
        check("Rodas5P", &Rodas5PScheme::TABLEAU, 5);
    }
}
