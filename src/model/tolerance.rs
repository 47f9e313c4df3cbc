//! A thread's tolerance class: the limits of size a drawing's designation (`M30x2-6g`,
//! `1/2-13 UNC-2B`, `Tr40x7-7e`) gives, and what the virtual gauges need to judge a cut
//! thread against them (the basic profile's flank angle and pitch, the length of
//! engagement, the NOT GO gauge's turns). Pure data: the tables and formulas that fill it
//! live in `model::standards`; the gauging itself in `analysis::gauge`.

/// The closed interval of a size (mm, diameters). An open end is infinite.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SizeLimits {
    /// Least size (mm); `f64::NEG_INFINITY` where the standard sets none.
    pub min: f64,
    /// Greatest size (mm); `f64::INFINITY` where the standard sets none.
    pub max: f64,
}

impl SizeLimits {
    /// Both ends given.
    pub fn new(min: f64, max: f64) -> SizeLimits {
        SizeLimits { min, max }
    }

    /// Whether `v` lies within the limits (inclusive).
    pub fn contains(&self, v: f64) -> bool {
        v >= self.min && v <= self.max
    }

    /// The middle of the zone (both ends finite), else the finite end, else `None`.
    pub fn mid(&self) -> Option<f64> {
        match (self.min.is_finite(), self.max.is_finite()) {
            (true, true) => Some(0.5 * (self.min + self.max)),
            (true, false) => Some(self.min),
            (false, true) => Some(self.max),
            (false, false) => None,
        }
    }
}

/// The unit system a designation is written in: the report gives inch threads in inches
/// and threads per inch beside millimetres.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UnitSystem {
    /// ISO metric (M, MJ, Tr, G, R designations).
    Metric,
    /// Inch (UN, UNC, UNF, UNEF, UNS, ACME, NPT).
    Inch,
}

/// The limits of size of one thread in one tolerance class, and the gauges' settings.
#[derive(Clone, Debug, PartialEq)]
pub struct ThreadClass {
    /// The designation as the drawing names it, normalised (`M30x2-6g`,
    /// `1/2-13 UNC-2B`).
    pub designation: String,
    /// The tolerance class alone (`6g`, `4h6h`, `2B`, `7e`); empty for a thread whose
    /// standard has none (a pipe thread gauged by its gauge plane).
    pub class: String,
    /// Metric or inch.
    pub units: UnitSystem,
    /// Whether the class is an internal thread's (H/G, B classes).
    pub internal: bool,
    /// Basic major diameter (mm).
    pub basic_major: f64,
    /// Basic pitch diameter (mm).
    pub basic_pitch_diameter: f64,
    /// Basic minor diameter of the internal thread, D1 (mm).
    pub basic_minor: f64,
    /// Pitch (mm): the axial distance between neighbouring threads.
    pub pitch: f64,
    /// Number of starts (lead = starts x pitch).
    pub starts: u32,
    /// Included flank angle of the basic profile (radians): 60 deg for ISO/UN, 30 deg Tr,
    /// 29 deg ACME, 55 deg BSP.
    pub flank_angle: f64,
    /// Taper on diameter per unit length (NPT, BSPT: 1/16); 0 for a parallel thread.
    pub taper: f64,
    /// Pitch diameter (mm): external d2 limits, internal D2 limits. For a taper thread,
    /// at the gauge plane.
    pub pitch_diameter: SizeLimits,
    /// Major diameter (mm): external d both limits; internal D a minimum only.
    pub major_diameter: SizeLimits,
    /// Minor diameter (mm): internal D1 both limits; external d3 a maximum (where the
    /// standard gives one) or none; ISO 965-1's root zone gives the external d3 both
    /// (d2 min − H + 2 C, C from `root`), ISO 2903 both (d3 − Td3 to d3).
    pub minor_diameter: SizeLimits,
    /// The length of engagement the GO gauge checks the functional size over (mm).
    pub engagement_length: f64,
    /// How many turns the NOT GO gauge may enter: 2 (ISO 1502), 3 (ASME B1.2).
    pub not_go_turns: f64,
    /// External threads with a rounded root (ISO 965-1): the root radius's least value and
    /// the root truncation's limits from the fundamental triangle's apex (mm).
    pub root: Option<RootZone>,
    /// A taper thread's gauge: where its gauge plane lies and how far the gauge may stand
    /// off it. `None` for a parallel thread.
    pub taper_gauge: Option<TaperGauge>,
    /// The sources the limits came from ("ISO 965-2 table", "ISO 965-1 formulas",
    /// "ASME B1.1 formulas"), for the report.
    pub source: String,
}

/// How a taper thread is gauged (ASME B1.20.1's L1 gauges, ISO 7-2's limit gauges): a
/// taper ring (external) or plug (internal) of the basic profile screwed on hand-tight
/// stops where its flanks meet the part's; its gauge plane must then lie within
/// `tolerance_turns` turns of the part's nominal one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TaperGauge {
    /// The gauge plane's distance from the thread's face into the part (mm): an external
    /// thread's gauge length (L1) from its small end, 0 for NPT internal (the L1 plug's
    /// notch flush with the face), half a pitch for ISO 7-1's Rc.
    pub gauge_plane: f64,
    /// The gauge's length of thread that engages from the face (mm).
    pub length: f64,
    /// The stand-off allowed either way (turns): 1 for NPT, ISO 7-1's T1/2 or T2/2.
    pub tolerance_turns: f64,
}

/// The root contour an external thread's class allows: rounded, of radius at least
/// `radius_min`, its lowest point between `truncation_min` and `truncation_max` above the
/// fundamental triangle's root apex (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RootZone {
    /// Least root radius (ISO 965-1: 0.125P).
    pub radius_min: f64,
    /// Least root truncation (the deepest root allowed, ISO 965-1: 0.125P).
    pub truncation_min: f64,
    /// Greatest root truncation (the shallowest root allowed).
    pub truncation_max: f64,
}
