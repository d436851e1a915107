//! The verdict on a conserved quantity (§5.5 of the thesis): the generated
//! `CONSERVED` constant of a system with `outputs { momenta }` holds one
//! per cyclic coordinate.

/// Whether the momentum conjugate to a cyclic coordinate is conserved, as
/// the macro decided it from the rate (5.36) it derived.
///
/// # Example
///
/// ```rust
/// use nh_runtime::Conservation;
///
/// let verdicts = [Conservation::Conserved, Conservation::NotConserved];
/// let kept = verdicts.iter().filter(|v| v.is_conserved()).count();
/// assert_eq!(kept, 1);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Conservation {
    /// The rate is identically zero: the engine reduced it to 0.
    Conserved,
    /// The rate is nonzero at some state (the generated documentation
    /// gives one).
    NotConserved,
    /// The rate vanished at every state sampled, but the engine did not
    /// reduce it to zero (an identity it does not know, or a rate that
    /// vanishes only on a set the samples kept hitting).
    Undecided,
}

impl Conservation {
    /// Whether the momentum is proved conserved.
    pub const fn is_conserved(self) -> bool {
        matches!(self, Conservation::Conserved)
    }
}
