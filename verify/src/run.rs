//! Many checks at once: a range of seeds on all cores, with the figures a
//! run reports (what kinds of systems were built, how each check ended).

use crate::check::{self, Finding, Report};
use crate::generate;
use crate::model::{Constraint, System};
use std::collections::BTreeMap;
use std::ops::Range;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// What a run of many checks found.
#[derive(Default, Debug)]
pub struct Summary {
    /// Systems checked.
    pub systems: usize,
    /// Systems whose every compared value agreed.
    pub agreed: usize,
    /// States compared in all.
    pub states: usize,
    /// The largest relative difference among the agreements (`f64`).
    pub worst: f64,
    /// The same for the generated code in double-double.
    pub worst_exact: f64,
    /// Systems the engine rejected, by the start of the first message.
    pub rejected: BTreeMap<String, Vec<u64>>,
    /// Systems with no comparable state, by reason.
    pub no_state: BTreeMap<String, Vec<u64>>,
    /// Disagreements and uninterpretable expansions: the reports.
    pub failures: Vec<Report>,
    /// How many systems had each feature.
    pub features: BTreeMap<&'static str, usize>,
    /// How many of the failures had each feature.
    pub failure_features: BTreeMap<&'static str, usize>,
    /// The momenta's check: systems with coordinates the plain derivation
    /// finds cyclic, expanded again with `outputs { momenta }`.
    pub momenta: MomentaTally,
    /// The declared momenta's check (`momenta { .. }` along the directions
    /// the rows allow, and rotations' turns): systems compared, momenta
    /// compared in them, and turns among those.
    pub declared: (usize, usize, usize),
    /// Systems with bodies that agreed again with every kinetic energy
    /// folded into a symbol of the Lagrangian.
    pub folded: usize,
    /// Of those, the systems whose second pass took the composite inertias.
    pub composite: usize,
    /// Of those, the systems whose second pass solved a reduced system by
    /// the articulated-body recursion.
    pub articulated: usize,
    /// Wall time.
    pub elapsed: Duration,
}

/// What the momenta's checks of a run found.
#[derive(Default, Debug)]
pub struct MomentaTally {
    /// Systems with coordinates found cyclic by the plain derivation.
    pub systems: usize,
    /// Of them, those whose momenta and rates were compared.
    pub compared: usize,
    /// Coordinates found cyclic in the systems compared.
    pub found: usize,
    /// Coordinates the engine listed in `CYCLIC`.
    pub listed: usize,
    /// The engine's refusals, by reason.
    pub refused: BTreeMap<String, usize>,
}

/// The features of a system, for the coverage figures.
pub fn features(sys: &System) -> Vec<&'static str> {
    let mut f = Vec::new();
    let text = sys.text();
    if sys.speeds.is_some() {
        f.push("speeds");
    }
    if !sys.bodies.is_empty() {
        f.push("bodies");
    }
    if sys.bodies.iter().any(|(_, b)| b.rotation.is_some()) {
        f.push("rigid bodies");
    }
    if sys.bodies.iter().any(|(_, b)| b.rotation.is_none()) {
        f.push("point masses");
    }
    if sys.bodies.iter().any(|(_, b)| !b.diagonal) {
        f.push("inertia with products");
    }
    for (kind, name) in [
        (0, "explicit constraints"),
        (1, "implicit constraints"),
        (2, "holonomic constraints"),
        (3, "rolling contacts"),
    ] {
        let has = sys.constraints.iter().any(|c| {
            matches!(
                (kind, c),
                (0, Constraint::Explicit { .. })
                    | (1, Constraint::Implicit { .. })
                    | (2, Constraint::Holonomic { .. })
                    | (3, Constraint::Rolls { .. })
            )
        });
        if has {
            f.push(name);
        }
    }
    if sys.timed_rows() {
        f.push("time-dependent constraints or kinematics");
    }
    if sys.timed(&sys.lagrangian) {
        f.push("time-dependent Lagrangian");
    }
    if !sys.inputs.is_empty() {
        f.push("inputs");
    }
    if !sys.forces.is_empty() {
        f.push("forces");
    }
    if text.contains("rot_z(") && text.contains(")*rot_") {
        f.push("rotation chains");
    }
    for o in &sys.outputs {
        f.push(match *o {
            "multipliers" => "output multipliers",
            "energy" => "output energy",
            "mass_matrix" => "output mass_matrix",
            "constraint_matrix" => "output constraint_matrix",
            _ => "output routes",
        });
    }
    f
}

/// Checks every seed of `seeds` on `threads` threads.
pub fn run(seeds: Range<u64>, threads: usize) -> Summary {
    let start = Instant::now();
    let next = Mutex::new(seeds.start);
    let reports = Mutex::new(Vec::new());
    std::thread::scope(|scope| {
        for _ in 0..threads.max(1) {
            scope.spawn(|| {
                loop {
                    let seed = {
                        let mut n = next.lock().unwrap_or_else(|e| e.into_inner());
                        if *n >= seeds.end {
                            break;
                        }
                        *n += 1;
                        *n - 1
                    };
                    let report = check::check(seed);
                    reports
                        .lock()
                        .unwrap_or_else(|e| e.into_inner())
                        .push(report);
                }
            });
        }
    });
    let mut reports = reports.into_inner().unwrap_or_else(|e| e.into_inner());
    reports.sort_by_key(|r| r.seed);
    let mut s = Summary {
        elapsed: start.elapsed(),
        ..Summary::default()
    };
    for r in reports {
        s.systems += 1;
        let tags = features(&generate::system(r.seed));
        for &f in &tags {
            *s.features.entry(f).or_default() += 1;
        }
        if let Finding::Disagree(_) | Finding::Uninterpretable(_) = r.finding {
            for f in tags {
                *s.failure_features.entry(f).or_default() += 1;
            }
        }
        s.folded += usize::from(r.folded);
        s.composite += usize::from(r.composite);
        s.articulated += usize::from(r.articulated);
        if let Some((momenta, turns)) = r.declared {
            s.declared.0 += 1;
            s.declared.1 += momenta;
            s.declared.2 += turns;
        }
        if let Some(c) = &r.cyclic {
            s.momenta.systems += 1;
            match &c.refused {
                Some(why) => *s.momenta.refused.entry(why.clone()).or_default() += 1,
                None => {
                    s.momenta.compared += 1;
                    s.momenta.found += c.found;
                    s.momenta.listed += c.listed;
                }
            }
        }
        match &r.finding {
            Finding::Agree {
                worst,
                worst_exact,
                states,
            } => {
                s.agreed += 1;
                s.states += states;
                s.worst = s.worst.max(*worst);
                s.worst_exact = s.worst_exact.max(*worst_exact);
            }
            Finding::Rejected(msgs) => {
                let key: String = msgs
                    .first()
                    .map_or("?", |m| m.as_str())
                    .chars()
                    .take(80)
                    .collect();
                s.rejected.entry(key).or_default().push(r.seed);
            }
            Finding::NoState(why) => {
                let key: String = why.chars().take(40).collect();
                s.no_state.entry(key).or_default().push(r.seed);
            }
            Finding::Disagree(_) | Finding::Uninterpretable(_) => s.failures.push(r),
        }
    }
    s
}

impl Summary {
    /// The figures as text.
    pub fn describe(&self) -> String {
        let mut out = format!(
            "{} systems in {:.1} s: {} agreed at {} states (worst relative difference {:.1e} in f64, {:.1e} in double-double), {} rejected by the engine, {} without a usable state, {} failures\n",
            self.systems,
            self.elapsed.as_secs_f64(),
            self.agreed,
            self.states,
            self.worst,
            self.worst_exact,
            self.rejected.values().map(Vec::len).sum::<usize>(),
            self.no_state.values().map(Vec::len).sum::<usize>(),
            self.failures.len()
        );
        let m = &self.momenta;
        out.push_str(&format!(
            "momenta: {} systems with coordinates cyclic by the plain derivation; {} expanded with `outputs {{ momenta }}` and compared ({} coordinates cyclic, {} listed in CYCLIC), {} refused\n",
            m.systems,
            m.compared,
            m.found,
            m.listed,
            m.refused.values().sum::<usize>()
        ));
        for (why, n) in &m.refused {
            out.push_str(&format!("  momenta refused: {n} × {why}\n"));
        }
        out.push_str(&format!(
            "declared momenta: {} systems expanded with a `momenta` block along the directions their rows allow and a rotation's turn, {} momenta and rates compared ({} turns)\n",
            self.declared.0, self.declared.1, self.declared.2
        ));
        out.push_str(&format!(
            "folded kinetic energies: {} systems with bodies agreed again with every kinetic energy folded into a symbol, {} of them with their bodies on chains of frames summed as composite inertias, {} solved by the articulated-body recursion\n",
            self.folded, self.composite, self.articulated
        ));
        out.push_str("features (systems, of them failing):\n");
        for (f, n) in &self.features {
            let failing = self.failure_features.get(f).copied().unwrap_or(0);
            out.push_str(&format!("  {n:6} {failing:5}  {f}\n"));
        }
        let seeds: Vec<String> = self.failures.iter().map(|r| r.seed.to_string()).collect();
        if !seeds.is_empty() {
            out.push_str(&format!("failing seeds: {}\n", seeds.join(" ")));
        }
        for (title, map) in [
            ("rejected", &self.rejected),
            ("no usable state", &self.no_state),
        ] {
            for (why, seeds) in map {
                let some: Vec<String> = seeds.iter().take(5).map(|s| s.to_string()).collect();
                out.push_str(&format!(
                    "{title}: {} × {why} (seeds {})\n",
                    seeds.len(),
                    some.join(", ")
                ));
            }
        }
        for r in self.failures.iter().take(10) {
            out.push_str(&format!(
                "FAILURE seed {} ({}): {:?}\n{}\n",
                r.seed, r.route, r.finding, r.text
            ));
        }
        out
    }
}
