//! Tool nose radius compensation (`nose`) against closed forms: the nose circle (its centre
//! the driven point less `r q`, `q` the tip direction) tangent to every programmed element of
//! a compensated contour, never inside it; start-up, cancel and corners as the manuals draw
//! them; the cycles; the controls' alarms. The oracle is the programmed contour's geometry,
//! computed here from the program's own numbers, never from the code under test.

use super::*;
use crate::model::Rng;
use glam::DVec2 as V2;

fn noses(r: f64, tip: u8) -> NoseData {
    NoseData {
        tool: [(1, (r, tip))].into(),
        ..NoseData::default()
    }
}

fn run_in(text: &str, dialect: Dialect, noses: NoseData) -> Result<Toolpath, NcError> {
    let src = Source {
        name: "T.NC".into(),
        text: text.into(),
    };
    interpret_with(
        &src,
        dialect,
        &|_| None,
        &Options {
            settings: Settings {
                noses,
                ..Settings::in_mm()
            },
            ..Options::default()
        },
    )
}

fn run(text: &str, r: f64, tip: u8) -> Vec<Move> {
    run_in(text, Dialect::Fanuc, noses(r, tip))
        .unwrap_or_else(|e| panic!("{e}\n{text}"))
        .moves
}

/// The tip vector of FANUC direction `tip` (the manual's table, written out here).
fn q(tip: u8) -> V2 {
    match tip {
        1 => V2::new(1.0, 1.0),
        2 => V2::new(-1.0, 1.0),
        3 => V2::new(-1.0, -1.0),
        4 => V2::new(1.0, -1.0),
        5 => V2::new(1.0, 0.0),
        6 => V2::new(0.0, 1.0),
        7 => V2::new(-1.0, 0.0),
        8 => V2::new(0.0, -1.0),
        _ => V2::ZERO,
    }
}

/// A move's start and end in `(z, r)`.
fn ends(m: &Move) -> (V2, V2) {
    (
        V2::new(m.z_start, m.x_start / 2.0),
        V2::new(m.z, m.x_dia / 2.0),
    )
}

/// The nose centre's path of a move driven at its tip: a segment, or an arc (centre,
/// radius, start, end, counter-clockwise).
enum Piece {
    Seg(V2, V2),
    Arc(V2, f64, V2, V2, bool),
}

fn centre_piece(m: &Move, r: f64, tip: u8) -> Piece {
    let (a, b) = ends(m);
    let d = q(tip) * r;
    match (m.kind, m.arc) {
        (MoveKind::Arc, Some(g)) => {
            let c = V2::new(g.z_centre, g.x_centre_dia / 2.0) - d;
            Piece::Arc(c, (a - d - c).length(), a - d, b - d, !g.clockwise)
        }
        _ => Piece::Seg(a - d, b - d),
    }
}

fn seg_dist(p: V2, a: V2, b: V2) -> f64 {
    let ab = b - a;
    let t = if ab.length_squared() == 0.0 {
        0.0
    } else {
        ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
    };
    (a + ab * t - p).length()
}

/// Whether the angle of `v` lies on the arc from `a` to `b` about the origin.
fn on_arc(v: V2, a: V2, b: V2, ccw: bool) -> bool {
    let ang = |w: V2| w.y.atan2(w.x);
    let tau = std::f64::consts::TAU;
    let (t0, t1, t) = (ang(a), ang(b), ang(v));
    let (sweep, off) = if ccw {
        ((t1 - t0).rem_euclid(tau), (t - t0).rem_euclid(tau))
    } else {
        ((t0 - t1).rem_euclid(tau), (t0 - t).rem_euclid(tau))
    };
    off <= sweep
}

fn piece_dist(p: V2, piece: &Piece) -> f64 {
    match *piece {
        Piece::Seg(a, b) => seg_dist(p, a, b),
        Piece::Arc(c, rad, a, b, ccw) => {
            let v = p - c;
            if v.length() > 0.0 && on_arc(v, a - c, b - c, ccw) {
                (v.length() - rad).abs()
            } else {
                (p - a).length().min((p - b).length())
            }
        }
    }
}

/// A programmed element in `(z, r)`: a line, or an arc (centre, counter-clockwise).
#[derive(Clone, Copy, Debug)]
struct Prog {
    a: V2,
    b: V2,
    arc: Option<(V2, bool)>,
}

impl Prog {
    fn points(&self, n: usize) -> Vec<V2> {
        (0..=n)
            .map(|k| {
                let t = k as f64 / n as f64;
                match self.arc {
                    None => self.a + (self.b - self.a) * t,
                    Some((c, ccw)) => {
                        let (va, vb) = (self.a - c, self.b - c);
                        let tau = std::f64::consts::TAU;
                        let sweep = if ccw {
                            (vb.y.atan2(vb.x) - va.y.atan2(va.x)).rem_euclid(tau)
                        } else {
                            -(va.y.atan2(va.x) - vb.y.atan2(vb.x)).rem_euclid(tau)
                        };
                        let ang = va.y.atan2(va.x) + sweep * t;
                        c + V2::new(ang.cos(), ang.sin()) * va.length()
                    }
                }
            })
            .collect()
    }
}

/// A random monotonic outer contour from the front (z = 0) towards -z, radius rising:
/// straight elements (along z, tapers, faces) and arcs (tangent fillets and bulged
/// elements), every element at least `min` long. Returns the elements and the program's
/// contour blocks (diameter programming, G01/G02/G03 with R).
fn contour(rng: &mut Rng, min: f64) -> Vec<Prog> {
    let mut pts = vec![V2::new(0.0, rng.range(6.0, 12.0))];
    let n = 3 + (rng.next() * 4.0) as usize;
    for k in 0..n {
        let p = *pts.last().unwrap();
        // Direction: from along -z (0 deg) to a face (90 deg), never the same twice.
        let ang = if k % 2 == 0 {
            rng.range(0.0, 10.0)
        } else {
            rng.range(20.0, 90.0)
        }
        .to_radians();
        let len = rng.range(min, 3.0 * min);
        pts.push(p + V2::new(-ang.cos(), ang.sin()) * len);
    }
    let mut out = Vec::new();
    for w in pts.windows(2) {
        let (a, b) = (w[0], w[1]);
        if rng.next() < 0.3 {
            // A bulged element: an arc through a and b, its sagitta a fifth of the chord,
            // bulging outwards (convex, clockwise going -z) or inwards.
            let chord = b - a;
            let h = chord.length() * 0.2 * if rng.next() < 0.5 { 1.0 } else { -1.0 };
            let mid = (a + b) * 0.5;
            let n = chord.perp().normalize();
            let peak = mid + n * h;
            // The circle through a, b and peak.
            let half = chord.length() / 2.0;
            let rad = (half * half + h * h) / (2.0 * h.abs());
            let c = peak - n * (rad * h.signum());
            let ccw = (a - c).perp_dot(peak - c) > 0.0;
            out.push(Prog {
                a,
                b,
                arc: Some((c, ccw)),
            });
        } else {
            out.push(Prog { a, b, arc: None });
        }
    }
    out
}

/// The FANUC program that turns `elems` with G42 (start-up at rapid `dz` in front of the
/// first element's start, on its radius; cancel straight up).
fn program(elems: &[Prog]) -> String {
    let p0 = elems[0].a;
    let mut s = format!(
        "O1\nG40 G99 T0101\nG00 X{:.6} Z{:.6}\nG00 G42 X{:.6} Z{:.6}\n",
        2.0 * (p0.y + 6.0),
        p0.x + 8.0,
        2.0 * p0.y,
        p0.x + 2.0
    );
    s.push_str(&format!("G01 Z{:.6} F0.2\n", p0.x));
    for e in elems {
        match e.arc {
            None => s.push_str(&format!("G01 X{:.6} Z{:.6}\n", 2.0 * e.b.y, e.b.x)),
            Some((c, ccw)) => s.push_str(&format!(
                "G0{} X{:.6} Z{:.6} I{:.6} K{:.6}\n",
                if ccw { 3 } else { 2 },
                2.0 * e.b.y,
                e.b.x,
                c.y - e.a.y,
                c.x - e.a.x
            )),
        }
    }
    let end = elems.last().unwrap().b;
    s.push_str(&format!("G00 G40 X{:.6}\nM30\n", 2.0 * (end.y + 5.0)));
    s
}

/// The program writes 6 decimals: an arc's end lies up to about 1e-6 off the circle through
/// its start, which the controls accept; the checks allow 1e-5.
#[test]
fn random_contours_keep_the_nose_tangent_to_every_element_and_never_inside() {
    let mut rng = Rng(0x2701);
    let mut checked = 0;
    for case in 0..200 {
        let r = rng.range(0.1, 1.2);
        let tip = [3u8, 3, 0, 8, 2, 7][case % 6];
        let elems = contour(&mut rng, 5.0 * r + 1.0);
        let text = program(&elems);
        let moves = run(&text, r, tip);
        // The contour with the element before it (G01 Z to its start, along -z).
        let mut all = vec![Prog {
            a: elems[0].a + V2::new(2.0, 0.0),
            b: elems[0].a,
            arc: None,
        }];
        all.extend(elems.iter().copied());
        // The compensated moves between the start-up and the cancel.
        let comp: Vec<&Move> = moves.iter().filter(|m| m.nose.is_some()).collect();
        assert!(comp.len() > all.len(), "case {case}: {comp:#?}");
        let pieces: Vec<Piece> = comp[1..].iter().map(|m| centre_piece(m, r, tip)).collect();
        // No point of the contour is nearer the nose centre than r: no gouge.
        for e in &all {
            for p in e.points(60) {
                let d = pieces
                    .iter()
                    .map(|pc| piece_dist(p, pc))
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    d > r - 1e-5,
                    "case {case}: the nose reaches {:.3e} inside the contour at {p:?}\n{text}",
                    r - d
                );
                checked += 1;
            }
        }
        // Each element's own compensated move runs at exactly r from it (tangent): its
        // centre's ends at distance r from the element's line or circle.
        for (k, e) in all.iter().enumerate() {
            let line = 4 + k; // the G01 Z block is line 4 (1-based): O1, G40, G00, G00 G42.
            let own: Vec<&Move> = comp
                .iter()
                .copied()
                .filter(|m| m.line == line + 1)
                .collect();
            let m = own
                .first()
                .unwrap_or_else(|| panic!("case {case}: no move of line {}", line + 1));
            let (a, b) = ends(m);
            let d = q(tip) * r;
            for c in [a - d, b - d] {
                let dist = match e.arc {
                    None => {
                        let t = (e.b - e.a).normalize();
                        // Signed: right of the direction of travel is negative (G42).
                        t.perp_dot(c - e.a)
                    }
                    Some((ctr, ccw)) => {
                        // Right of a counter-clockwise arc is outside.
                        let out = (c - ctr).length() - (e.a - ctr).length();
                        if ccw {
                            -out
                        } else {
                            out
                        }
                    }
                };
                assert!(
                    (dist + r).abs() < 1e-5,
                    "case {case} element {k}: the centre lies {dist} from it, not -{r}\n{text}"
                );
            }
        }
    }
    assert!(checked > 10_000);
}

#[test]
fn a_compensated_chamfer_puts_the_nose_on_the_drawn_line() {
    // A 45 deg chamfer C1 from X20 Z0 to X22 Z-1 then along X22, G42, nose 0.8, tip 3:
    // the nose centre runs on the chamfer's line moved 0.8 outwards (normal (1, 1)/sqrt 2
    // in (z, r)), the driven tip 0.8 (-1, -1) from it. Closed form of the tip's end on the
    // chamfer: the intersection of the two offset lines (the corner to Z-line is outer,
    // 135 deg inside): r = 11 + 0.8 on the Z-line, on the chamfer line offset:
    // z + r = -1 + 11 + 0.8 sqrt 2 -> z = -1 + 0.8 (sqrt 2 - 1) - 0.8 ... worked below.
    let r: f64 = 0.8;
    let text = "O1\nT0101\nG00 X30.0 Z3.0\nG00 G42 X18.0 Z1.0\nG01 X22.0 Z-1.0 F0.1\nZ-10.0\nG00 G40 X30.0\nM30\n";
    let m = run(text, r, 3);
    let s2 = 2f64.sqrt();
    // Start-up (type A): to (z, r) = (1, 9) + r n, n the chamfer's right normal
    // (1, 1)/sqrt 2 (G42 on a line going (-1, +1)), then the tip: - r (1, 1).
    let (_, b) = ends(&m[1]);
    let want = V2::new(1.0, 9.0) + V2::new(1.0, 1.0) * (r / s2) - V2::new(r, r);
    assert!((b - want).length() < 1e-12, "{b:?} vs {want:?}");
    // The chamfer's end: the offset chamfer line z + r = 10 + r sqrt 2 meets r = 11 + 0.8.
    let (_, b) = ends(&m[2]);
    let centre = V2::new(10.0 + r * s2 - (11.0 + r), 11.0 + r);
    assert!((b - (centre - V2::new(r, r))).length() < 1e-12, "{b:?}");
    // Every chamfer centre point is r from the chamfer line: tangent.
    for p in [ends(&m[2]).0, ends(&m[2]).1] {
        let c = p + V2::new(r, r);
        let d = (c.x + c.y - 10.0) / s2;
        assert!((d - r).abs() < 1e-12, "{d}");
    }
    // The uncompensated program leaves the chamfer r (2 - sqrt 2) high in radius: the nose
    // centre r (1, 1) from the tip on the line z + r = 10 lies r sqrt 2 from it, its nose
    // r (sqrt 2 - 1) off the line, r (2 - sqrt 2) along the radius.
    let plain = run(&text.replace("G42 ", "").replace("G40 ", ""), r, 3);
    let (a, _) = ends(&plain[2]);
    let c = a + V2::new(r, r);
    let normal_gap = (c.x + c.y - 10.0) / s2 - r;
    assert!((normal_gap - r * (s2 - 1.0)).abs() < 1e-12);
    assert!((normal_gap * s2 - r * (2.0 - s2)).abs() < 1e-12);
}

#[test]
fn arcs_keep_their_centre_at_radius_r_plus_or_minus_the_nose() {
    // A convex R5 quarter (G03 from X20 Z0 to X30 Z-5 about (z -5, r 10)... written as
    // G02/G03 on the outside of a part) and a concave one; G42, nose 0.4, tip 3.
    for (g, r_prog, outside) in [(3, 5.0, true), (2, 5.0, false)] {
        let r = 0.4;
        let text = format!(
            "O1\nT0101\nG00 X10.0 Z5.0\nG00 G42 X10.0 Z2.0\nG01 Z0.0 F0.1\nG0{g} X20.0 Z-5.0 R{r_prog}\nG01 Z-10.0\nG00 G40 X40.0\nM30\n"
        );
        let m = run(&text, r, 3);
        let arc = m
            .iter()
            .find(|m| m.line == 6 && m.kind == MoveKind::Arc)
            .unwrap();
        let g_arc = arc.arc.unwrap();
        // The tip's arc is about the programmed centre moved by r q = (-r, -r).
        let (a, b) = ends(arc);
        let c = V2::new(g_arc.z_centre, g_arc.x_centre_dia / 2.0);
        let rad = (a - c).length();
        // The R5 arc from (z, r) = (0, 5) to (-5, 10): G02 (clockwise) about (0, 10), a
        // concave fillet with the nose inside its circle (5 - r); G03 about (-5, 5), a
        // rounded edge with the nose outside (5 + r).
        let want = if outside { r_prog + r } else { r_prog - r };
        assert!((rad - want).abs() < 1e-9, "G0{g}: {rad} vs {want}");
        assert!(((b - c).length() - want).abs() < 1e-9);
        let prog_c = if g == 2 {
            V2::new(0.0, 10.0)
        } else {
            V2::new(-5.0, 5.0)
        };
        assert!((c - (prog_c - V2::new(r, r))).length() < 1e-9, "{c:?}");
    }
}

#[test]
fn tip_directions_move_the_driven_point_and_not_the_nose() {
    // The same contour with every tip direction: the driven points differ by r (q - q3),
    // the nose centre's path is the same.
    let text = "O1\nT0101\nG00 X30.0 Z2.0\nG00 G42 X20.0 Z1.0\nG01 Z-5.0 F0.1\nX26.0 Z-8.0\nZ-12.0\nG00 G40 X40.0\nM30\n";
    let r = 0.5;
    let base = run(text, r, 3);
    for tip in 0..=9u8 {
        let m = run(text, r, tip);
        assert_eq!(m.len(), base.len());
        for (x, y) in m
            .iter()
            .zip(&base)
            .filter(|(x, _)| x.nose.is_some())
            .skip(1)
        {
            let (a, b) = ends(x);
            let (a3, b3) = ends(y);
            let shift = (q(tip) - q(3)) * r;
            assert!((a - a3 - shift).length() < 1e-12, "tip {tip}");
            assert!((b - b3 - shift).length() < 1e-12, "tip {tip}");
        }
    }
}

#[test]
fn corners_inner_outer_and_acute_as_the_fanuc_manual_draws_them() {
    let r = 0.5;
    // Inner corner (a shoulder rising from a Z-line, G42 outside): the centre at the
    // intersection of r = 10 + 0.5 and z = -5 + 0.5.
    let text = "O1\nT0101\nG00 X30.0 Z2.0\nG00 G42 X20.0 Z1.0\nG01 Z-5.0 F0.1\nX30.0\nZ-9.0\nG00 G40 X40.0\nM30\n";
    let m = run(text, r, 0);
    let (_, b) = ends(&m[2]);
    assert!((b - V2::new(-4.5, 10.5)).length() < 1e-12, "{b:?}");
    // Outer corner of 90 deg inside (the shoulder's top, then along -z): the offset lines
    // z = -4.5 and r = 15.5 meet at (-4.5, 15.5).
    let (_, b) = ends(&m[3]);
    assert!((b - V2::new(-4.5, 15.5)).length() < 1e-12, "{b:?}");
    // Acute outer corner: a face going up then a line back down towards +z (a lip):
    // inside angle 45 deg. FANUC: the face's offset line extended by r past its
    // perpendicular, then to the second line's offset start less r along it.
    let text = "O1\nT0101\nG00 X30.0 Z2.0\nG00 G41 X20.0 Z-5.0\nG01 X30.0 F0.1\nX20.0 Z0.0\nG00 G40 X50.0\nM30\n";
    let m = run(text, r, 0);
    // Face from (-5, 10) to (-5, 15), G41: left of +r is -z: offset z = -5.5. Corner at
    // (-5, 15), next direction (1, -1)/sqrt 2, its left normal (1, 1)/sqrt 2.
    let s2 = 2f64.sqrt();
    let p1 = V2::new(-5.5, 15.0) + V2::new(0.0, r);
    let start_j = V2::new(-5.0, 15.0) + V2::new(1.0, 1.0) * (r / s2);
    let p2 = start_j - V2::new(1.0, -1.0) * (r / s2);
    let (_, b) = ends(&m[2]);
    assert!((b - p1).length() < 1e-12, "{b:?} vs {p1:?}");
    let (a, b) = ends(&m[3]);
    assert!(
        (a - p1).length() < 1e-12 && (b - p2).length() < 1e-12,
        "{a:?} {b:?}"
    );
    // The corner's point is never nearer the centre path than r.
    let corner = V2::new(-5.0, 15.0);
    assert!(seg_dist(corner, p1, p2) >= r - 1e-12);
}

#[test]
fn start_up_and_cancel_are_type_a() {
    // Start-up G00 G42 to (z 1, r 10), the next block along -z: the end vector is r
    // perpendicular to the next block (up), the tip r(q) from it. Cancel from the last
    // block's perpendicular to the programmed end.
    let r = 0.4;
    let text =
        "O1\nT0101\nG00 X30.0 Z5.0\nG00 G42 X20.0 Z1.0\nG01 Z-8.0 F0.1\nG00 G40 X30.0 Z-8.0\nM30\n";
    let m = run(text, r, 3);
    let (a, b) = ends(&m[1]);
    assert!((a - V2::new(5.0, 15.0)).length() < 1e-12);
    assert!(
        (b - (V2::new(1.0, 10.4) - V2::new(r, r))).length() < 1e-12,
        "{b:?}"
    );
    let (a, b) = ends(&m[3]);
    assert!(
        (a - (V2::new(-8.0, 10.4) - V2::new(r, r))).length() < 1e-12,
        "{a:?}"
    );
    assert!((b - V2::new(-8.0, 15.0)).length() < 1e-12);
    assert!(m[3].nose.is_none() && m[2].nose.is_some());
}

#[test]
fn the_controls_alarms() {
    let err = |text: &str, d: Dialect| run_in(text, d, noses(0.8, 3)).unwrap_err();
    // FANUC: start-up in an arc.
    let e = err(
        "O1\nT0101\nG00 X30.0 Z2.0\nG02 G42 X20.0 Z-3.0 R5.0 F0.1\nM30\n",
        Dialect::Fanuc,
    );
    assert!(e.message.contains("PS0034"), "{e}");
    assert_eq!(e.line, 4);
    // The nose does not fit in a concave R0.5 (G42 outside, a G03 fillet going up).
    let e = err(
        "O1\nT0101\nG00 X30.0 Z2.0\nG00 G42 X20.0 Z1.0\nG01 Z-5.0 F0.1\nG02 X21.0 Z-5.5 R0.5\nG01 Z-8.0\nG00 G40 X40.0\nM30\n",
        Dialect::Fanuc,
    );
    assert!(e.message.contains("R - r <= 0"), "{e}");
    // Cancel in an arc.
    let e = err(
        "O1\nT0101\nG00 X30.0 Z2.0\nG00 G42 X20.0 Z1.0\nG01 Z-5.0 F0.1\nG40 G02 X30.0 Z-10.0 R5.0\nM30\n",
        Dialect::Fanuc,
    );
    assert!(e.message.contains("G40"), "{e}");
    // LinuxCNC: an entry move shorter than the radius, comp on when on.
    let lc = |body: &str| format!("G18 G21 G7\nT1 M6\nG0 X30 Z5\n{body}M2\n");
    let e = err(&lc("G42 G1 X30 Z4.5 F1\nZ0\nG40 X40\n"), Dialect::Linuxcnc);
    assert!(e.message.contains("entry move is not greater"), "{e}");
    let e = err(
        &lc("G42 G1 X20 Z0 F1\nG41 Z-5\nG40 X40\n"),
        Dialect::Linuxcnc,
    );
    assert!(e.message.contains("on when on"), "{e}");
}

#[test]
fn roughing_cuts_to_the_compensated_shape_and_finishing_runs_it() {
    // G42 before G71 (FANUC 0i-TF): the roughing's last pass along the shape moved by the
    // allowance is the compensated shape moved by it; G70 runs the compensated shape.
    let r = 0.8;
    let shape = "N10 G00 X20.0\nN20 G01 Z-10.0 F0.1\nN30 X30.0 Z-20.0\nN40 Z-30.0\nN50 X40.0\n";
    let text = format!(
        "O1\nT0101\nG00 G42 X42.0 Z2.0\nG71 U1.0 R0.5\nG71 P10 Q50 U0.4 W0.1 F0.2\n{shape}G70 P10 Q50\nG00 G40 X60.0 Z10.0\nM30\n"
    );
    let m = run(&text, r, 3);
    let plain = run(&text.replace("G42 ", "").replace("G40 ", ""), r, 3);
    // G70's moves (keeping the shape's lines, 6..10) compensated: the taper's centre r off
    // it.
    let taper = m.iter().find(|x| x.line == 8 && x.nose.is_some()).unwrap();
    let (a, b) = ends(taper);
    for p in [a, b] {
        let c = p + V2::new(r, r);
        // The taper from (z -10, r 10) to (-20, 15): direction (-10, 5); right normal.
        let t = V2::new(-10.0, 5.0).normalize();
        let d = t.perp_dot(c - V2::new(-10.0, 10.0));
        assert!((d + r).abs() < 1e-9, "{d}");
    }
    // G71's moves are held (as made) and end on the compensated shape plus the allowance:
    // its last pass along the taper lies r off the taper moved by (0.2, 0.1).
    let g71: Vec<&Move> = m.iter().filter(|x| x.line == 5).collect();
    assert!(g71.iter().all(|x| x.nose.is_none()));
    let along = g71
        .iter()
        .rev()
        .find(|x| {
            let (a, b) = ends(x);
            let d = b - a;
            x.kind == MoveKind::Feed && d.x < 0.0 && d.y > 0.0 && (d.y / d.x + 0.5).abs() < 1e-9
        })
        .expect("the last pass along the taper");
    let (a, _) = ends(along);
    let c = a + V2::new(r, r);
    let t = V2::new(-10.0, 5.0).normalize();
    let d = t.perp_dot(c - V2::new(-10.0 + 0.1, 10.0 + 0.2));
    assert!((d + r).abs() < 1e-9, "{d}");
    // Without compensation the same cycle's taper pass runs on the programmed taper.
    assert!(plain.iter().all(|x| x.nose.is_none()));
}

#[test]
fn threading_under_compensation_is_held_and_said() {
    let text = "O1\nT0101\nG00 G42 X32.0 Z5.0\nG76 P010060 Q100 R0.05\nG76 X27.546 Z-20.0 P1227 Q400 F2.0\nG00 G40 X40.0\nM30\n";
    let tp = run_in(text, Dialect::Fanuc, noses(0.4, 3)).unwrap();
    let plain = run_in(&text.replace("G42 ", ""), Dialect::Fanuc, noses(0.4, 3)).unwrap();
    let threads = |t: &Toolpath| -> Vec<(f64, f64, f64, f64)> {
        t.moves
            .iter()
            .filter(|m| m.kind == MoveKind::Thread)
            .map(|m| (m.x_start, m.z_start, m.x_dia, m.z))
            .collect()
    };
    assert_eq!(threads(&tp), threads(&plain));
    assert!(tp
        .warnings
        .iter()
        .any(|w| w.message.contains("tool nose radius compensation on")));
}

#[test]
fn siemens_transition_circles_and_intersections() {
    // G450 (the default): an arc of radius r about the outer corner; G451: the offset
    // lines' intersection.
    let r = 0.5;
    let body = |g: &str| {
        format!("T1 D1\n{g}\nG0 X30 Z2\nG0 G42 X20 Z1\nG1 Z-5 F0.1\nX30\nZ-9\nG0 G40 X40\nM30\n")
    };
    let d = |t: &str| {
        run_in(t, Dialect::Siemens802d, noses(r, 0))
            .unwrap_or_else(|e| panic!("{e}"))
            .moves
    };
    let arc = d(&body("G450"));
    let corner = arc
        .iter()
        .find(|m| m.kind == MoveKind::Arc)
        .expect("a transition arc");
    let g = corner.arc.unwrap();
    assert!((g.z_centre + 5.0).abs() < 1e-12 && (g.x_centre_dia - 30.0).abs() < 1e-12);
    let (a, b) = ends(corner);
    assert!(
        (a - V2::new(-4.5, 15.0)).length() < 1e-12 && (b - V2::new(-5.0, 15.5)).length() < 1e-12
    );
    let meet = d(&body("G451"));
    assert!(meet.iter().all(|m| m.kind != MoveKind::Arc));
    assert!(meet
        .iter()
        .any(|m| (ends(m).1 - V2::new(-4.5, 15.5)).length() < 1e-12));
}

#[test]
fn offsets_page_radius_and_tip_override_the_tool() {
    // T0105 calls offset 5 whose page says R 1.0, T 8: the compensation uses them.
    let mut n = noses(0.4, 3);
    n.offset.insert(
        5,
        NoseOffset {
            radius: Some(1.0),
            wear: -0.2,
            tip: Some(8),
        },
    );
    let text =
        "O1\nT0105\nG00 X30.0 Z2.0\nG00 G42 X20.0 Z1.0\nG01 Z-5.0 F0.1\nG00 G40 X30.0\nM30\n";
    let m = run_in(text, Dialect::Fanuc, n).unwrap().moves;
    let nz = m[2].nose.unwrap();
    assert_eq!((nz.radius, nz.tip), (0.8, 8));
    // Tip 8 is (0, -1): the driven point on the diameter the nose touches.
    let (_, b) = ends(&m[2]);
    assert!((b - V2::new(-5.0, 10.0)).length() < 1e-12, "{b:?}");
}

#[test]
fn siemens_kont_goes_round_the_start_point_behind_the_contour() {
    // G42 KONT from (z 2, r 8), behind the contour that starts at (0, 10) going -z (the
    // start lies below, on the material side): NORM would put the nose straight at the
    // perpendicular (0, 10.5) through the material; KONT goes round (0, 10) on a circle of
    // the radius (G450): the approach ends 0.5 right of itself, then an arc about (0, 10)
    // to (0, 10.5).
    let r = 0.5;
    let text = |kont: &str| {
        format!("T1 D1\nG0 X16 Z2\nG0 G42 {kont} X20 Z0\nG1 Z-8 F0.1\nG0 G40 X40\nM30\n")
    };
    let run = |t: &str| {
        run_in(t, Dialect::Siemens802d, noses(r, 0))
            .unwrap_or_else(|e| panic!("{e}"))
            .moves
    };
    let norm = run(&text("NORM"));
    assert!((ends(&norm[1]).1 - V2::new(0.0, 10.5)).length() < 1e-12);
    let kont = run(&text("KONT"));
    // The approach (2, 8) -> (0, 10): direction (-1, 1)/sqrt 2, its right normal (1, 1)/sqrt 2.
    let s2 = 2f64.sqrt();
    let end = V2::new(0.0, 10.0) + V2::new(1.0, 1.0) * (r / s2);
    assert!(
        (ends(&kont[1]).1 - end).length() < 1e-12,
        "{:?}",
        ends(&kont[1])
    );
    let arc = &kont[2];
    assert_eq!(arc.kind, MoveKind::Arc);
    let g = arc.arc.unwrap();
    assert!((g.z_centre).abs() < 1e-12 && (g.x_centre_dia - 20.0).abs() < 1e-12);
    assert!((ends(arc).1 - V2::new(0.0, 10.5)).length() < 1e-12);
    // In front of the contour (from above) KONT is NORM.
    let front = |kont: &str| {
        format!("T1 D1\nG0 X30 Z2\nG0 G42 {kont} X20 Z0\nG1 Z-8 F0.1\nG0 G40 X40\nM30\n")
    };
    let path = |m: Vec<Move>| -> Vec<(V2, V2)> { m.iter().map(ends).collect() };
    assert_eq!(path(run(&front("KONT"))), path(run(&front("NORM"))));
}

#[test]
fn okuma_compensates_with_the_nose_number_of_its_t_code() {
    // T010102: offset 01, tool 01, nose R compensation number 02, whose page says R 1.2.
    let mut n = noses(0.4, 3);
    n.offset.insert(
        2,
        NoseOffset {
            radius: Some(1.2),
            ..NoseOffset::default()
        },
    );
    let text = "$A.MIN%\nO1\nN1 T010102\nN2 G00 X30 Z2\nN3 G42 G00 X20 Z1\nN4 G01 Z-5 F0.1\nN5 G40 G00 X30\nN6 M02\n%\n";
    let m = run_in(text, Dialect::Okuma, n).unwrap().moves;
    let nz = m[2].nose.unwrap();
    assert_eq!((nz.radius, nz.tip, nz.rule), (1.2, 3, NoseRule::Fanuc));
    // The diameter's end before G40: centre r 10 + 1.2, the tip 1.2 (-1, -1) from it.
    let (_, b) = ends(&m[2]);
    assert!((b - V2::new(-6.2, 10.0)).length() < 1e-12, "{b:?}");
}
