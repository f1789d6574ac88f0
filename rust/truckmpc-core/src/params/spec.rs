//! The kinds of a parameter's value and their admissible ranges, and how both read in words.

/// The type of a parameter's value, as a user writes it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A finite number.
    Number,
    /// A finite number, or null.
    NumberOrNull,
    /// A whole number.
    Count,
    /// A whole number, or null.
    CountOrNull,
    /// true or false.
    Flag,
    /// One of a few names.
    Choice(&'static [&'static str]),
    /// A list of finite numbers.
    Numbers,
    /// A list of finite numbers with nulls where an entry does not apply.
    NumbersOrNulls,
}

impl Kind {
    /// The kind's name as the binding reports it (`"number"`, `"choice"`, ...).
    pub fn name(&self) -> &'static str {
        match self {
            Kind::Number => "number",
            Kind::NumberOrNull => "number_or_null",
            Kind::Count => "count",
            Kind::CountOrNull => "count_or_null",
            Kind::Flag => "flag",
            Kind::Choice(_) => "choice",
            Kind::Numbers => "numbers",
            Kind::NumbersOrNulls => "numbers_or_nulls",
        }
    }
}

/// One end of a range.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Bound {
    /// No limit on this side.
    Open,
    /// The value itself is allowed.
    Inclusive(f64),
    /// Only values strictly beyond it are allowed.
    Exclusive(f64),
}

/// The admissible values of a number (or of each number of a list).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range {
    /// Lower end.
    pub lo: Bound,
    /// Upper end.
    pub hi: Bound,
}

impl Range {
    /// Any finite number.
    pub const ANY: Range = Range { lo: Bound::Open, hi: Bound::Open };
    /// > 0.
    pub const POSITIVE: Range = Range { lo: Bound::Exclusive(0.0), hi: Bound::Open };
    /// >= 0.
    pub const NON_NEGATIVE: Range = Range { lo: Bound::Inclusive(0.0), hi: Bound::Open };
    /// >= 1 (counts).
    pub const AT_LEAST_ONE: Range = Range { lo: Bound::Inclusive(1.0), hi: Bound::Open };
    /// (0, 1]: efficiencies, time steps in seconds.
    pub const FRACTION: Range = Range { lo: Bound::Exclusive(0.0), hi: Bound::Inclusive(1.0) };

    /// (0, hi]: a positive quantity with a physical upper limit (no truck weighs 1e308 kg; values
    /// that large overflow the model's products into infinities and NaN).
    pub const fn positive_up_to(hi: f64) -> Range {
        Range { lo: Bound::Exclusive(0.0), hi: Bound::Inclusive(hi) }
    }

    /// [lo, hi].
    pub const fn between(lo: f64, hi: f64) -> Range {
        Range { lo: Bound::Inclusive(lo), hi: Bound::Inclusive(hi) }
    }

    /// Whether `x` is finite and within the range.
    pub fn contains(&self, x: f64) -> bool {
        let above = match self.lo {
            Bound::Open => true,
            Bound::Inclusive(lo) => x >= lo,
            Bound::Exclusive(lo) => x > lo,
        };
        let below = match self.hi {
            Bound::Open => true,
            Bound::Inclusive(hi) => x <= hi,
            Bound::Exclusive(hi) => x < hi,
        };
        x.is_finite() && above && below
    }

    /// The range as text after a noun: `" > 0"`, `" in (0, 1]"`, or `""` for any number.
    pub fn text(&self) -> String {
        match (self.lo, self.hi) {
            (Bound::Open, Bound::Open) => String::new(),
            (Bound::Inclusive(lo), Bound::Open) => format!(" >= {lo}"),
            (Bound::Exclusive(lo), Bound::Open) => format!(" > {lo}"),
            (Bound::Open, Bound::Inclusive(hi)) => format!(" <= {hi}"),
            (Bound::Open, Bound::Exclusive(hi)) => format!(" < {hi}"),
            (lo, hi) => {
                let (open, lo) = match lo {
                    Bound::Inclusive(x) => ('[', x),
                    Bound::Exclusive(x) => ('(', x),
                    Bound::Open => ('(', f64::NEG_INFINITY),
                };
                let (close, hi) = match hi {
                    Bound::Inclusive(x) => (']', x),
                    Bound::Exclusive(x) => (')', x),
                    Bound::Open => (')', f64::INFINITY),
                };
                format!(" in {open}{lo}, {hi}{close}")
            }
        }
    }
}

/// What a value of `kind` within `range` is, in words.
pub fn expected_text(kind: Kind, range: &Range) -> String {
    let r = range.text();
    match kind {
        Kind::Number => format!("a number{r}"),
        Kind::NumberOrNull => format!("a number{r} or null"),
        Kind::Count => format!("a whole number{r}"),
        Kind::CountOrNull => format!("a whole number{r} or null"),
        Kind::Flag => "true or false".to_string(),
        Kind::Choice(names) => names.iter().map(|n| format!("'{n}'")).collect::<Vec<_>>().join(" or "),
        Kind::Numbers => format!("a list of numbers{r}"),
        Kind::NumbersOrNulls => format!("a list of numbers{r} (or null where an entry does not apply)"),
    }
}

/// Doc comment lines joined into one line.
pub fn join_doc(lines: &[&str]) -> String {
    lines.iter().map(|l| l.trim()).filter(|l| !l.is_empty()).collect::<Vec<_>>().join(" ")
}
