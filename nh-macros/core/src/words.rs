//! The words of the input language, each typed once: the blocks
//! (`parameters { .. }`, ...), the other keywords (`let`, `lagrangian`,
//! `body`, `rolls`), the outputs (`energy`, ...), the functions of the
//! expressions (`sin`, ..., `cross`, ...) and the constants (`t`, `pi`).
//!
//! Each kind of word is an enum, and [`words!`] writes each word's spelling
//! once, next to its variant: the parser reads a word into its enum, later
//! stages match the enum, and a misspelling is answered from the same enum
//! ("did you mean `constraints`?").

use crate::names;
use proc_macro2::Ident;
use std::fmt;

/// The enums of words: each variant with its spelling (and the other
/// spellings it is read from, `Centre = "centre" | "center"`), and for each
/// enum `ALL` (in the order the messages list them, which is the order of
/// the variants), `name`, `parse`, `of`, `closest` and `suggest`, also as
/// the trait [`Word`].
macro_rules! words {
    ($(
        $(#[$doc:meta])*
        pub enum $kind:ident {
            $( $(#[$variant_doc:meta])* $variant:ident = $name:literal $(| $alias:literal)*, )+
        }
    )+) => {$(
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum $kind {
            $( $(#[$variant_doc])* $variant, )+
        }

        impl $kind {
            /// Every word of the kind, in the order the messages list them.
            pub const ALL: [$kind; [$($name),+].len()] = [$($kind::$variant),+];

            /// The word as written.
            pub const fn name(self) -> &'static str {
                match self {
                    $( $kind::$variant => $name, )+
                }
            }

            /// The word spelled `text`, if there is one.
            pub fn parse(text: &str) -> Option<$kind> {
                match text {
                    $( $name $(| $alias)* => Some($kind::$variant), )+
                    _ => None,
                }
            }

            /// The word an identifier spells, if it spells one.
            pub fn of(id: &Ident) -> Option<$kind> {
                $kind::parse(&id.to_string())
            }

            /// The word `text` is probably a misspelling of: the closest
            /// within a small distance (never `text` itself).
            pub fn closest(text: &str) -> Option<$kind> {
                names::closest(text, $kind::ALL.map($kind::name)).and_then($kind::parse)
            }

            /// `" (did you mean `word`?)"` for the word closest to `text`,
            /// or the empty string.
            pub fn suggest(text: &str) -> String {
                names::suggest(text, &$kind::ALL.map($kind::name))
            }
        }

        impl fmt::Display for $kind {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(self.name())
            }
        }

        impl PartialEq<$kind> for Ident {
            fn eq(&self, word: &$kind) -> bool {
                self == word.name()
            }
        }

        impl Word for $kind {
            fn all() -> &'static [$kind] {
                &$kind::ALL
            }

            fn name(self) -> &'static str {
                $kind::name(self)
            }

            fn parse(text: &str) -> Option<$kind> {
                $kind::parse(text)
            }

            fn suggest(text: &str) -> String {
                $kind::suggest(text)
            }
        }
    )+};
}

/// A kind of word, for code that works on any of them (the fields of a
/// `body` and the named arguments of `rolls(..)` are checked by one
/// function).
pub trait Word: Copy + Eq + fmt::Display + 'static {
    /// Every word of the kind, in the order the messages list them.
    fn all() -> &'static [Self];
    /// The word as written.
    fn name(self) -> &'static str;
    /// The word spelled `text`, if there is one.
    fn parse(text: &str) -> Option<Self>;
    /// `" (did you mean `word`?)"` for the word closest to `text`, or the
    /// empty string.
    fn suggest(text: &str) -> String;
}

words! {
    /// A block of a definition, `keyword { .. }`.
    pub enum Block {
        /// `parameters { m, g }`: the constants, fields of the struct
        Parameters = "parameters",
        /// `coordinates { x, theta }`: the generalized coordinates
        Coordinates = "coordinates",
        /// `inputs { F }`: the inputs, arguments of the methods
        Inputs = "inputs",
        /// `forces { x: F; }`: the generalized forces
        Forces = "forces",
        /// `constraints { dot(y) = ..; }`: the velocity constraints and
        /// rolling contacts
        Constraints = "constraints",
        /// `dependent { s }`: the coordinates the implicit and holonomic
        /// constraints are solved for
        Dependent = "dependent",
        /// `speeds { v, omega }`: the generalized speeds
        Speeds = "speeds",
        /// `kinematics { dot(x) = v*cos(theta); }`: q̇ in the speeds
        Kinematics = "kinematics",
        /// `outputs { energy }`: the opt-in outputs
        Outputs = "outputs",
        /// `symmetries { turn(x: -y, y: x, phi: 1); }`: one-parameter
        /// groups, each by its generator
        Symmetries = "symmetries",
        /// `momenta { K_x(Q: [1, 0, 0], y: -R); }`: momenta along motions
        /// the constraints allow, each by its direction
        Momenta = "momenta",
    }

    /// The words that start an item (`let`, `lagrangian`, `body`) other
    /// than the blocks, and `rolls`, which starts a rolling contact's line
    /// of `constraints`.
    pub enum Keyword {
        /// `let NAME = expr;`
        Let = "let",
        /// `lagrangian = expr;`
        Lagrangian = "lagrangian",
        /// `body NAME { .. }`
        Body = "body",
        /// `rolls(BODY, radius: .., ..);`
        Rolls = "rolls",
        /// `skates(BODY, across: d[, at: p]);`
        Skates = "skates",
        /// `slides(BODY[, at: p][, on: ..]);`
        Slides = "slides",
    }

    /// An opt-in output (DESIGN §3), or `routes`.
    pub enum Output {
        /// `multipliers`
        Multipliers = "multipliers",
        /// `curvature`
        Curvature = "curvature",
        /// `energy`
        Energy = "energy",
        /// `constraint_matrix`
        ConstraintMatrix = "constraint_matrix",
        /// `mass_matrix`
        MassMatrix = "mass_matrix",
        /// `jacobian`
        Jacobian = "jacobian",
        /// `linearization`: A = ∂f/∂x and B = ∂f/∂u
        Linearization = "linearization",
        /// `routes`: both derivation routes as separate methods
        Routes = "routes",
        /// `reaction_forces`: E − Q of a system in generalized speeds (DESIGN §9)
        ReactionForces = "reaction_forces",
        /// `contact_points`: the contact points of the rolling contacts (DESIGN §10)
        ContactPoints = "contact_points",
        /// `sensitivities` (or `sensitivities(p, ..)`): ∂f/∂p and the variational
        /// equations, for forward sensitivities; implies `jacobian`
        Sensitivities = "sensitivities",
        /// `momenta`: the momenta conjugate to the cyclic coordinates and
        /// their rates (§5.5), with a verdict on each
        Momenta = "momenta",
    }

    /// A function of the expressions: the scalar functions, `dot` (the
    /// time derivative, and the dot product of two vectors) and the
    /// functions of vectors, rotations and bodies. A name is a function only
    /// where it is called, so `abs` or `atan` can still name a coordinate.
    pub enum Function {
        /// sine
        Sin = "sin",
        /// cosine
        Cos = "cos",
        /// tangent
        Tan = "tan",
        /// cotangent
        Cot = "cot",
        /// secant
        Sec = "sec",
        /// cosecant
        Csc = "csc",
        /// inverse sine
        Asin = "asin",
        /// inverse cosine
        Acos = "acos",
        /// inverse tangent
        Atan = "atan",
        /// `atan2(y, x)`: the angle of the point (x, y)
        Atan2 = "atan2",
        /// hyperbolic sine
        Sinh = "sinh",
        /// hyperbolic cosine
        Cosh = "cosh",
        /// hyperbolic tangent
        Tanh = "tanh",
        /// exponential
        Exp = "exp",
        /// natural logarithm
        Ln = "ln",
        /// square root
        Sqrt = "sqrt",
        /// absolute value
        Abs = "abs",
        /// `dot(q)`: the time derivative; `dot(a, b)`: the dot product
        Dot = "dot",
        /// `cross(a, b)`: the cross product
        Cross = "cross",
        /// `norm(v)`: the length of a vector
        Norm = "norm",
        /// `transpose(R)`
        Transpose = "transpose",
        /// `rot_x(angle)`: the rotation about the x axis
        RotX = "rot_x",
        /// `rot_y(angle)`: the rotation about the y axis
        RotY = "rot_y",
        /// `rot_z(angle)`: the rotation about the z axis
        RotZ = "rot_z",
        /// `diag(a, b, c)`: a diagonal matrix
        Diag = "diag",
        /// `omega(R)`: the angular velocity, world components
        Omega = "omega",
        /// `omega_body(R)`: the angular velocity, body components
        OmegaBody = "omega_body",
        /// `kinetic_energy(body)`
        KineticEnergy = "kinetic_energy",
    }

    /// A constant of the expressions: a name no item declares.
    pub enum Constant {
        /// `t`: time
        Time = "t",
        /// `pi`: π
        Pi = "pi",
    }

    /// A field of a `body` item, `body NAME { mass: .., centre: .., .. }`.
    pub enum BodyField {
        /// `mass: m`
        Mass = "mass",
        /// `centre: C`, the centre of mass (also spelled `center`)
        Centre = "centre" | "center",
        /// `orientation: R`, body to world
        Orientation = "orientation",
        /// `inertia: I`, about the centre of mass in body axes
        Inertia = "inertia",
    }

    /// A named argument of a rolling contact, `rolls(BODY, radius: .., ..)`.
    pub enum RollingField {
        /// `radius: r`
        Radius = "radius",
        /// `axle: [..]`, the wheel's axis of symmetry in body axes
        Axle = "axle",
        /// `tube: ρ`, the tube radius of a torus
        Tube = "tube",
        /// `centre: G`, the geometric centre if not the centre of mass
        /// (also spelled `center`)
        Centre = "centre" | "center",
        /// `semi_axes: [a, b, c]`, an ellipsoid's semi-axes along the body
        /// axes
        SemiAxes = "semi_axes",
        /// `on: F`, the support: a rotation or a body, whose plane z = 0
        /// the body rolls on; or `on: z = h(x, y)`, a fixed surface
        On = "on",
        /// `origin: O`, a point of the support's plane (by default the
        /// origin, or the supporting body's centre)
        Origin = "origin",
        /// `inside: sphere(..)` or `cylinder(..)`, a fixed surface a ball
        /// rolls in
        Inside = "inside",
        /// `outside: sphere(..)` or `cylinder(..)`, a fixed surface a ball
        /// rolls on
        Outside = "outside",
        /// `rail: d`, the line (direction d in the plane's axes, through its
        /// origin) the contact point keeps to
        Rail = "rail",
        /// `contact: [u, v]`, the coordinates that are the contact point's
        /// x and y on a surface `on: z = h(x, y)`
        Contact = "contact",
        /// `support_function: h(x, y, z)`, a strictly convex body's
        /// support function in body axes
        SupportFunction = "support_function",
    }

    /// A named argument of a skate or knife edge, `skates(BODY, across: ..)`.
    pub enum SkateField {
        /// `across: d`, the body-fixed direction the point does not move along
        Across = "across",
        /// `at: p`, the body point (body axes, from the centre of mass)
        At = "at",
    }

    /// A named argument of a point kept on a surface, `slides(BODY, ..)`.
    pub enum SlideField {
        /// `at: p`, the body point (body axes, from the centre of mass)
        At = "at",
        /// `on: z = h(x, y)`, the surface; or `on: F`, a support whose
        /// plane z = 0 the point keeps to
        On = "on",
        /// `origin: O`, a point of the support's plane
        Origin = "origin",
    }

    /// A component of a vector, `v.x`.
    pub enum Component {
        /// `v.x`
        X = "x",
        /// `v.y`
        Y = "y",
        /// `v.z`
        Z = "z",
    }
}

impl Component {
    /// The component's index, 0 for `x`.
    pub fn index(self) -> usize {
        match self {
            Component::X => 0,
            Component::Y => 1,
            Component::Z => 2,
        }
    }
}

/// A word as written where a word of kind `W` is expected: the identifier
/// (its text and span, for the messages) and the word it spells, if any.
#[derive(Clone, Debug)]
pub struct Spelled<W> {
    /// The identifier as written.
    pub ident: Ident,
    /// The word it spells, if it spells one.
    pub word: Option<W>,
}

impl Spelled<Output> {
    /// The output as written, read.
    pub fn new(ident: Ident) -> Spelled<Output> {
        let word = Output::of(&ident);
        Spelled { ident, word }
    }

    /// The output meant: the one written, or the one it is closest to (a
    /// misspelling).
    pub fn meant(&self) -> Option<Output> {
        self.word
            .or_else(|| Output::closest(&self.ident.to_string()))
    }
}

impl<W> fmt::Display for Spelled<W> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.ident.fmt(f)
    }
}

impl Block {
    /// Whether the block is a comma-separated list of names.
    pub fn lists_names(self) -> bool {
        matches!(
            self,
            Block::Parameters
                | Block::Coordinates
                | Block::Inputs
                | Block::Speeds
                | Block::Outputs
                | Block::Dependent
        )
    }
}

impl Keyword {
    /// Whether the keyword starts an item (`rolls` starts a line).
    pub fn starts_item(self) -> bool {
        self != Keyword::Rolls
    }
}

impl Function {
    /// The axis (0 for x, 1 for y, 2 for z) of an elementary rotation
    /// `rot_x`, `rot_y` or `rot_z`.
    pub fn rotation_axis(self) -> Option<usize> {
        match self {
            Function::RotX => Some(0),
            Function::RotY => Some(1),
            Function::RotZ => Some(2),
            _ => None,
        }
    }

    /// Whether it is a function of vectors, rotations or bodies (`dot`,
    /// also the time derivative, is not counted among them).
    pub fn of_vectors(self) -> bool {
        matches!(
            self,
            Function::Cross
                | Function::Norm
                | Function::Transpose
                | Function::RotX
                | Function::RotY
                | Function::RotZ
                | Function::Diag
                | Function::Omega
                | Function::OmegaBody
                | Function::KineticEnergy
        )
    }

    /// Whether it is a scalar function: of one argument (`sin` .. `abs`)
    /// or `atan2`; not `dot` nor a function of vectors.
    pub fn is_scalar(self) -> bool {
        self != Function::Dot && !self.of_vectors()
    }

    /// Whether its name cannot be declared: `dot` and the first functions
    /// of the language. The functions added later are not reserved, so a
    /// coordinate, parameter or `let` named `abs`, `atan` or `sinh` keeps
    /// working.
    pub fn is_reserved(self) -> bool {
        matches!(
            self,
            Function::Dot
                | Function::Sin
                | Function::Cos
                | Function::Tan
                | Function::Exp
                | Function::Ln
                | Function::Sqrt
        )
    }

    /// The scalar functions and `dot` as the messages list them: "`sin`,
    /// `cos`, ..., `abs` and `dot` (time derivative)".
    pub fn listed() -> String {
        let names = Function::ALL
            .into_iter()
            .filter(|f| !f.of_vectors())
            .map(Function::name);
        format!("{} (time derivative)", and_list(names))
    }
}

/// Whether `text` is a word that cannot be declared as a name: a constant
/// (`t`, `pi`) or a reserved function ([`Function::is_reserved`]).
pub fn is_reserved(text: &str) -> bool {
    Constant::parse(text).is_some() || Function::parse(text).is_some_and(Function::is_reserved)
}

/// Words for a message: "`a`, `b` and `c`".
pub fn and_list<'a>(words: impl IntoIterator<Item = &'a str>) -> String {
    let quoted: Vec<String> = words.into_iter().map(|w| format!("`{w}`")).collect();
    match quoted.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => quoted.concat(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proc_macro2::Span;

    /// Every word's name parses back to it, and its identifier too.
    macro_rules! round_trip {
        ($($kind:ident),+) => {$(
            for w in $kind::ALL {
                assert_eq!($kind::parse(w.name()), Some(w), "{w}");
                let id = Ident::new(w.name(), Span::call_site());
                assert_eq!($kind::of(&id), Some(w));
                assert!(id == w);
                assert_eq!(w.to_string(), w.name());
            }
            assert_eq!($kind::parse("unknown"), None);
        )+};
    }

    #[test]
    fn every_word_parses_back_from_its_name() {
        round_trip!(
            Block,
            Keyword,
            Output,
            Function,
            Constant,
            BodyField,
            RollingField
        );
    }

    /// The same through [`Word`], as code generic over the kind sees it.
    fn round_trip_as_word<W: Word + fmt::Debug>() {
        for &w in W::all() {
            assert_eq!(W::parse(w.name()), Some(w));
            assert_eq!(w.to_string(), w.name());
        }
        assert_eq!(W::parse("unknown"), None);
    }

    #[test]
    fn every_word_parses_back_as_a_word() {
        round_trip_as_word::<Block>();
        round_trip_as_word::<Function>();
        round_trip_as_word::<BodyField>();
        round_trip_as_word::<RollingField>();
        round_trip_as_word::<SkateField>();
        round_trip_as_word::<SlideField>();
        assert_eq!(<BodyField as Word>::all(), BodyField::ALL);
        assert_eq!(
            <RollingField as Word>::suggest("radus"),
            RollingField::suggest("radus")
        );
    }

    #[test]
    fn the_fields_of_bodies_and_rolling_contacts() {
        assert_eq!(
            BodyField::ALL.map(BodyField::name),
            ["mass", "centre", "orientation", "inertia"]
        );
        assert_eq!(
            RollingField::ALL.map(RollingField::name),
            [
                "radius",
                "axle",
                "tube",
                "centre",
                "semi_axes",
                "on",
                "origin",
                "inside",
                "outside",
                "rail",
                "contact",
                "support_function"
            ]
        );
        // `center` is read as `centre`, which is the name written back
        assert_eq!(BodyField::parse("center"), Some(BodyField::Centre));
        assert_eq!(RollingField::parse("center"), Some(RollingField::Centre));
        let id = Ident::new("center", Span::call_site());
        assert_eq!(BodyField::of(&id), Some(BodyField::Centre));
        assert_eq!(BodyField::Centre.name(), "centre");
        // a field of one is not one of the other
        assert_eq!(BodyField::parse("radius"), None);
        assert_eq!(RollingField::parse("mass"), None);
        assert_eq!(BodyField::parse("Mass"), None);
    }

    #[test]
    fn misspelt_fields_are_answered_from_their_enum() {
        assert_eq!(BodyField::closest("mas"), Some(BodyField::Mass));
        assert_eq!(BodyField::closest("intertia"), Some(BodyField::Inertia));
        assert_eq!(
            BodyField::closest("orientaton"),
            Some(BodyField::Orientation)
        );
        assert_eq!(BodyField::suggest("mas"), " (did you mean `mass`?)");
        assert_eq!(BodyField::suggest("radius"), "");
        assert_eq!(RollingField::closest("radus"), Some(RollingField::Radius));
        assert_eq!(RollingField::closest("axel"), Some(RollingField::Axle));
        assert_eq!(RollingField::suggest("tub"), " (did you mean `tube`?)");
        assert_eq!(RollingField::suggest("mass"), "");
    }

    #[test]
    fn the_axes_of_the_rotations() {
        assert_eq!(Function::RotX.rotation_axis(), Some(0));
        assert_eq!(Function::RotY.rotation_axis(), Some(1));
        assert_eq!(Function::RotZ.rotation_axis(), Some(2));
        let axes = Function::ALL
            .into_iter()
            .filter_map(Function::rotation_axis)
            .count();
        assert_eq!(axes, 3);
    }

    #[test]
    fn the_variants_are_listed_in_order() {
        for (i, o) in Output::ALL.into_iter().enumerate() {
            assert_eq!(o as usize, i);
        }
        for (i, b) in Block::ALL.into_iter().enumerate() {
            assert_eq!(b as usize, i);
        }
        for (i, f) in Function::ALL.into_iter().enumerate() {
            assert_eq!(f as usize, i);
        }
    }

    #[test]
    fn each_word_is_parsed() {
        assert_eq!(Block::parse("parameters"), Some(Block::Parameters));
        assert_eq!(Block::parse("coordinates"), Some(Block::Coordinates));
        assert_eq!(Block::parse("inputs"), Some(Block::Inputs));
        assert_eq!(Block::parse("forces"), Some(Block::Forces));
        assert_eq!(Block::parse("constraints"), Some(Block::Constraints));
        assert_eq!(Block::parse("dependent"), Some(Block::Dependent));
        assert_eq!(Block::parse("speeds"), Some(Block::Speeds));
        assert_eq!(Block::parse("kinematics"), Some(Block::Kinematics));
        assert_eq!(Block::parse("outputs"), Some(Block::Outputs));
        assert_eq!(Keyword::parse("let"), Some(Keyword::Let));
        assert_eq!(Keyword::parse("lagrangian"), Some(Keyword::Lagrangian));
        assert_eq!(Keyword::parse("body"), Some(Keyword::Body));
        assert_eq!(Keyword::parse("rolls"), Some(Keyword::Rolls));
        assert_eq!(Output::parse("energy"), Some(Output::Energy));
        assert_eq!(
            Output::parse("constraint_matrix"),
            Some(Output::ConstraintMatrix)
        );
        assert_eq!(Output::parse("sensitivities"), Some(Output::Sensitivities));
        assert_eq!(Function::parse("atan2"), Some(Function::Atan2));
        assert_eq!(Function::parse("rot_z"), Some(Function::RotZ));
        assert_eq!(
            Function::parse("kinetic_energy"),
            Some(Function::KineticEnergy)
        );
        assert_eq!(Constant::parse("t"), Some(Constant::Time));
        assert_eq!(Constant::parse("pi"), Some(Constant::Pi));
        // the spelling is exact: no case folding, no plural
        assert_eq!(Block::parse("Parameters"), None);
        assert_eq!(Block::parse("constraint"), None);
        assert_eq!(Output::parse("Energy"), None);
        // a word of one kind is not one of another
        assert_eq!(Block::parse("let"), None);
        assert_eq!(Function::parse("t"), None);
        assert_eq!(Output::parse("sin"), None);
    }

    #[test]
    fn misspellings_are_answered_from_the_same_enum() {
        assert_eq!(Block::closest("constraint"), Some(Block::Constraints));
        assert_eq!(Block::closest("paramters"), Some(Block::Parameters));
        assert_eq!(Block::closest("kinematic"), Some(Block::Kinematics));
        assert_eq!(Block::closest("zzz"), None);
        // a word is not a misspelling of itself, only of another word
        assert_eq!(Block::closest("speeds"), None);
        assert_eq!(Block::closest("inputs"), Some(Block::Outputs));
        assert_eq!(
            Block::suggest("constraint"),
            " (did you mean `constraints`?)"
        );
        assert_eq!(Block::suggest("zzz"), "");
        assert_eq!(Output::closest("energie"), Some(Output::Energy));
        assert_eq!(Output::closest("jacobain"), Some(Output::Jacobian));
        assert_eq!(
            Output::suggest("mass_matrx"),
            " (did you mean `mass_matrix`?)"
        );
        assert_eq!(Keyword::closest("lagrangain"), Some(Keyword::Lagrangian));
        assert_eq!(Function::closest("cso"), Some(Function::Cos));
        assert_eq!(Function::closest("atna"), Some(Function::Atan));
        assert_eq!(Function::closest("crosss"), Some(Function::Cross));
        let span = Span::call_site();
        let spelled = Spelled::<Output>::new(Ident::new("energie", span));
        assert_eq!(spelled.word, None);
        assert_eq!(spelled.meant(), Some(Output::Energy));
        assert_eq!(spelled.to_string(), "energie");
        let spelled = Spelled::<Output>::new(Ident::new("energy", span));
        assert_eq!(spelled.word, Some(Output::Energy));
        assert_eq!(spelled.meant(), Some(Output::Energy));
    }

    #[test]
    fn kinds_of_words() {
        let names: Vec<Block> = Block::ALL.into_iter().filter(|b| b.lists_names()).collect();
        assert_eq!(
            names,
            [
                Block::Parameters,
                Block::Coordinates,
                Block::Inputs,
                Block::Dependent,
                Block::Speeds,
                Block::Outputs
            ]
        );
        assert!(Keyword::Let.starts_item() && !Keyword::Rolls.starts_item());
        let scalar = Function::ALL.into_iter().filter(|f| f.is_scalar()).count();
        assert_eq!(scalar, 17);
        assert!(Function::Atan2.is_scalar() && !Function::Dot.is_scalar());
        assert!(Function::Cross.of_vectors() && !Function::Dot.of_vectors());
        for word in ["t", "pi", "dot", "sin", "cos", "tan", "exp", "ln", "sqrt"] {
            assert!(is_reserved(word), "{word}");
        }
        for word in ["abs", "atan", "sinh", "cross", "x", "energy"] {
            assert!(!is_reserved(word), "{word}");
        }
    }

    #[test]
    fn lists_for_the_messages() {
        assert_eq!(and_list(["a"]), "`a`");
        assert_eq!(and_list(["a", "b", "c"]), "`a`, `b` and `c`");
        assert_eq!(and_list([]), "");
        assert_eq!(
            and_list(Block::ALL.map(Block::name)),
            "`parameters`, `coordinates`, `inputs`, `forces`, `constraints`, `dependent`, `speeds`, `kinematics`, `outputs`, `symmetries` and `momenta`"
        );
        assert_eq!(
            Function::listed(),
            "`sin`, `cos`, `tan`, `cot`, `sec`, `csc`, `asin`, `acos`, `atan`, `atan2`, `sinh`, `cosh`, `tanh`, `exp`, `ln`, `sqrt`, `abs` and `dot` (time derivative)"
        );
    }

    #[test]
    fn the_components_of_a_vector() {
        let names: Vec<_> = Component::ALL.iter().map(|c| c.name()).collect();
        assert_eq!(names, ["x", "y", "z"]);
        let indices: Vec<_> = Component::ALL.iter().map(|c| c.index()).collect();
        assert_eq!(indices, [0, 1, 2]);
        assert_eq!(Component::parse("w"), None);
    }
}
