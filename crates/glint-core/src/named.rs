//! Named choices: the closed sets a user picks from by name in scene files and on the command
//! line (integrators, samplers, filters, light sampling, intersection methods). Each set lists
//! its members and their names once, here in its `Named` impl; the readers and the CLI parse
//! from that list, so a new member needs no mirror anywhere else.

pub trait Named: Copy + Send + Sync + 'static {
    /// Every member, in the order help texts list them.
    const ALL: &'static [Self];

    /// The member's name in scene files and on the command line.
    fn name(self) -> &'static str;

    fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|k| k.name() == name)
    }

    /// Every name, comma-separated (for messages that list the choices).
    fn names() -> String {
        Self::ALL.iter().map(|k| k.name()).collect::<Vec<_>>().join(", ")
    }
}
