//! Roads from OpenCRG files (`.crg`, ASCII and binary) and ISO 8608 random roads (docs/roads.md).
//!
//! The file is read by the `opencrg` crate (pure Rust, the reader the `xodr` crate uses for OpenDRIVE's CRG
//! surfaces; it follows the ASAM OpenCRG 2.0 C-API, border modes and `$ROAD_CRG_MODS` included). This
//! module adds what the vehicle model needs around it:
//!
//! - **Bounded reading**: at most `MAX_CRG_BYTES`, regular files only (`bounded_read`), errors naming the file;
//!   a file that declares more points than it holds, a zero increment or non-numeric data is the crate's error,
//!   prefixed with the file name.
//! - **Placement**: the road's reference-line start (u at its start, v = 0) is put `START_BEHIND_REAR_AXLE_M`
//!   behind the vehicle's initial rear axle, on the vehicle's centre line, the reference line's heading along
//!   the vehicle's x axis; queries are turned from the simulation's ground frame into the road's x, y.
//! - **Heights in double precision**: the crate evaluates the grid bilinearly in f64; it stores the grid's
//!   values in f32 (a relative 6e-8: 3e-8 m on a 0.5 m obstacle, far below the 1e-6 m the check against an
//!   independent reader asks); the gradient comes from its surface normal.
//! - **Extent**: the u and v ranges of the grid. Outside, the border modes the file declares decide (the
//!   crate applies them; `inside` reports it, and the simulation logs an event, `wheel … left the extent of
//!   …`). Where the file declares none (`NO_BORDER`), or mode 0, there is no surface: `off_road` names the
//!   position and the extent, and the run ends with it as its error.
//! - **Closed tracks**: a reference line that ends where it starts (`Closure`) is lapped, u wrapping.
//! - **Includes** (`$ROAD_CRG_FILE`): read (bounded, checked as the including file is) relative to the
//!   including file's folder.
//! - **Sharing**: a file loads once per process; FMU instances naming the same file (same path, length and
//!   modification time) share it (`load`).
use super::surface::{FileRoad, Placement, Road};
use opencrg::{BorderMode, CrgGrid, LoadOptions, Uv, Xy};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, Weak};

/// The largest height a road file may hold or its header put the surface at, m: beyond ±1 km is no road
/// (the highest paved road is 5.8 km up, but a file's heights are relative to its own start), it is a damaged
/// value (a float read from the wrong bytes is typically 1e38).
pub const MAX_HEIGHT_M: f64 = 1000.0;
/// The largest road file read: 512 MiB (a 100 km road at 1 cm with 5 long sections in f32 is 200 MB).
pub const MAX_CRG_BYTES: u64 = 512 << 20;
/// Where the reference line starts, behind the vehicle's initial rear axle, m.
pub const START_BEHIND_REAR_AXLE_M: f64 = 2.0;

/// A loaded surface: the grid and its name (the file, or the ISO 8608 specification).
pub struct Surface {
    pub name: String,
    pub grid: CrgGrid,
    /// Whether the border modes continue the surface beyond the grid's u ends and v sides (a mode the file
    /// declares in `$ROAD_CRG_OPTS` other than 0; without one there is no surface beyond: `NO_BORDER`).
    open: [bool; 2],
    /// The lap of a closed reference line (`Closure`), if the line closes.
    closed: Option<Closure>,
}

/// A reference line that ends where it starts: its last cross section lies a gap `gap` (at most
/// `CLOSING_GAP_INCREMENTS` increments, 0.2 m on Chrono's circles and 0.18 m on Barber) before its first,
/// heading the same way (within `CLOSING_HEADING_RAD`). u then wraps with the period `lap` = u range + gap,
/// and the gap is bridged linearly from the last cross section to the first (as a grid cell is).
#[derive(Debug, Clone, Copy)]
struct Closure {
    gap: f64,
    lap: f64,
}

/// How far the last cross section may lie before the first, in increments, for the line to be closed.
pub const CLOSING_GAP_INCREMENTS: f64 = 2.5;
/// How far the end's heading may differ from the start's for the line to be closed, rad (6°).
pub const CLOSING_HEADING_RAD: f64 = 0.1;

/// The application's border mode where the file declares none (OpenCRG lets the application choose; the
/// C-API's is 2, keep the last value): no surface, so that leaving the grid is an error naming the
/// position, never a surface the file does not hold.
pub const NO_BORDER: BorderMode = BorderMode::None;

impl std::fmt::Debug for Surface {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Surface({})", self.name)
    }
}

impl Surface {
    /// A surface from the bytes of a CRG file named `name` (for messages); includes are refused.
    pub fn from_bytes(name: &str, bytes: &[u8]) -> Result<Surface, String> {
        Surface::from_bytes_in(name, bytes, None)
    }

    /// A surface from the bytes of a CRG file named `name`, its `$ROAD_CRG_FILE` includes read from the
    /// folder `dir` (the including file's; `None`: includes are refused).
    fn from_bytes_in(name: &str, bytes: &[u8], dir: Option<&Path>) -> Result<Surface, String> {
        let (prepared, asked) = prepare(name, bytes)?;
        let continuation = std::cell::Cell::new(asked);
        let mut options = LoadOptions::default();
        (options.border_mode_u, options.border_mode_v) = (NO_BORDER, NO_BORDER);
        let included = std::cell::Cell::new(false);
        let grid = CrgGrid::from_bytes_with(&prepared, &options, |include: &str| {
            included.set(true);
            let Some(dir) = dir else {
                return Err(std::io::Error::other("includes ($ROAD_CRG_FILE) are read only from a file's folder"));
            };
            if include.contains('$') {
                return Err(std::io::Error::other("environment variables in include names are not expanded"));
            }
            let path = dir.join(include);
            let what = format!("the road file {} (included by {name})", path.display());
            let bytes = bounded_read::read_bytes(&path, MAX_CRG_BYTES, &what).map_err(std::io::Error::other)?;
            let (prepared, more) = prepare(&path.display().to_string(), &bytes).map_err(std::io::Error::other)?;
            continuation.set(continuation.get() || more);
            Ok(prepared)
        })
        .map_err(|e| format!("road file {name}: {e}"))?;
        let bytes = &prepared[..];
        let (nu, nv) = grid.dims();
        // The crate reads the complete records it finds; a file that declares more (truncated, or a header
        // promising 10⁸ points over a few rows) is refused rather than read short.
        if let Some(declared) = declared_cross_sections(bytes).filter(|_| !included.get()) {
            if declared != nu {
                return Err(format!(
                    "road file {name}: its header declares {declared} cross sections (REFERENCE_LINE_START_U, END_U, \
                     INCREMENT) and its data hold {nu}: truncated, or a wrong header"
                ));
            }
        }
        if nu < 2 || nv < 1 {
            return Err(format!("road file {name}: {nu} cross sections of {nv} points: not a surface"));
        }
        let [u0, u1] = range(grid.u_range());
        let [v0, v1] = range(grid.v_range());
        if !(u1 > u0) || !(v1 >= v0) || ![u0, u1, v0, v1].iter().all(|x| x.is_finite()) {
            return Err(format!("road file {name}: its extent u {u0}..{u1}, v {v0}..{v1} m is not a surface"));
        }
        // The border modes as loaded: probe just beyond each edge (the crate applies the file's modes).
        let probe = |uv: Uv| grid.elevation_at_uv(uv).is_some();
        let mid = Uv { u: 0.5 * (u0 + u1), v: 0.5 * (v0 + v1) };
        if !probe(mid) {
            return Err(format!("road file {name}: no height at the middle of the grid (NaN data?)"));
        }
        let open = [probe(Uv { u: u1 + 1.0, ..mid }), probe(Uv { v: v1 + 1.0, ..mid })];
        check_heights(name, &grid)?;
        let closed = closure(&grid);
        if continuation.get() && closed.is_none() {
            return Err(format!(
                "road file {name}: REFLINE_CONTINUATION = 1 asks for a closed track, and its reference line does \
                 not end where it starts (within {CLOSING_GAP_INCREMENTS} increments, {CLOSING_HEADING_RAD} rad)"
            ));
        }
        Ok(Surface { name: name.to_string(), grid, open, closed })
    }

    /// Reads a CRG file (bounded), its includes relative to its folder.
    fn read(path: &Path) -> Result<Surface, String> {
        let name = path.display().to_string();
        let bytes = bounded_read::read_bytes(path, MAX_CRG_BYTES, &format!("the road file {name}"))?;
        let dir = path.parent().map_or_else(|| PathBuf::from("."), Path::to_path_buf);
        Surface::from_bytes_in(&name, &bytes, Some(&dir))
    }

    /// The grid's u and v ranges, m.
    pub fn extent(&self) -> ([f64; 2], [f64; 2]) {
        (range(self.grid.u_range()), range(self.grid.v_range()))
    }

    /// The length of a lap when the reference line is closed (u wraps), m.
    pub fn lap(&self) -> Option<f64> {
        self.closed.map(|c| c.lap)
    }
}

/// A file's bytes checked (`check_ascii_data`, `check_binary_data`) and made ready for the crate: long
/// sections centred where the file says so (`centre_long_sections`), and `REFLINE_CONTINUATION` taken out
/// (the crate refuses a closed track's continuation; this module laps it, `Closure`) and returned.
fn prepare(name: &str, bytes: &[u8]) -> Result<(Vec<u8>, bool), String> {
    check_ascii_data(name, bytes)?;
    check_binary_data(name, bytes)?;
    let centred = centre_long_sections(bytes);
    Ok(take_continuation(centred.as_deref().unwrap_or(bytes)))
}

/// The header without its `REFLINE_CONTINUATION` option (the line commented out, `*` in the first column),
/// and whether it asked for the closed track (1).
fn take_continuation(bytes: &[u8]) -> (Vec<u8>, bool) {
    let head_len = data_layout(bytes).map_or(bytes.len().min(64 << 10), |l| l.start);
    // A header that is not UTF-8 text is left as it is (the crate's own reading names what is wrong).
    let Ok(head) = std::str::from_utf8(&bytes[..head_len]) else { return (bytes.to_vec(), false) };
    let mut out = Vec::with_capacity(bytes.len() + 2);
    let mut asked = false;
    for line in head.split_inclusive('\n') {
        let option = line.split_once('=').filter(|(k, _)| k.trim().eq_ignore_ascii_case("REFLINE_CONTINUATION"));
        if let Some((_, value)) = option {
            asked |= value.split('!').next().and_then(|v| v.trim().parse::<f64>().ok()) == Some(1.0);
            out.extend_from_slice(b"* ");
        }
        out.extend_from_slice(line.as_bytes());
    }
    out.extend_from_slice(&bytes[head_len..]);
    (out, asked)
}

/// The closure of a reference line (`Closure`), from the grid's reference line as loaded (modifiers applied).
fn closure(grid: &CrgGrid) -> Option<Closure> {
    let ([u0, u1], inc) = (range(grid.u_range()), (grid.u_range().1 - grid.u_range().0) / (grid.dims().0 - 1) as f64);
    let (start, end) = (grid.xy_from_uv(Uv { u: u0, v: 0.0 }), grid.xy_from_uv(Uv { u: u1, v: 0.0 }));
    let (phi0, phi1) = (grid.heading_at_uv(Uv { u: u0, v: 0.0 }).phi, grid.heading_at_uv(Uv { u: u1, v: 0.0 }).phi);
    let (dx, dy) = (start.x - end.x, start.y - end.y);
    let gap = dx.hypot(dy);
    let turn = (phi0 - phi1).sin().atan2((phi0 - phi1).cos()).abs();
    // The start lies ahead of the end along its heading (not beside or behind it).
    let ahead = dx * phi1.cos() + dy * phi1.sin() > 0.9 * gap;
    (gap > 0.0 && gap <= CLOSING_GAP_INCREMENTS * inc && turn <= CLOSING_HEADING_RAD && ahead)
        .then_some(Closure { gap, lap: u1 - u0 + gap })
}

/// A file that gives the long sections' increment but neither LONG_SECTION_V_RIGHT nor _LEFT has them
/// centred on the reference line (OpenCRG's `handmade_straight_minimalist.crg` says it is "completely
/// equivalent" to `handmade_straight.crg`, which declares −1.5 … 1.5 m). The `opencrg` crate puts the
/// first long section at v = 0 instead (its README: the C-API uses 0 there); the check against PyOpenCRG
/// (tests/roads.rs) found it. Here the header gains LONG_SECTION_V_RIGHT = −(n − 1)·increment/2 before the
/// crate reads it: the copy of the bytes, or `None` when nothing is to be added.
fn centre_long_sections(bytes: &[u8]) -> Option<Vec<u8>> {
    let head_len = bytes.len().min(64 << 10);
    let head = String::from_utf8_lossy(&bytes[..head_len]);
    let has =
        |key: &str| head.lines().any(|l| l.split_once('=').is_some_and(|(k, _)| k.trim().eq_ignore_ascii_case(key)));
    if has("LONG_SECTION_V_RIGHT") || has("LONG_SECTION_V_LEFT") {
        return None;
    }
    let increment = head.lines().find_map(|l| {
        let (k, v) = l.split_once('=')?;
        k.trim()
            .eq_ignore_ascii_case("LONG_SECTION_V_INCREMENT")
            .then(|| v.split('!').next()?.trim().parse::<f64>().ok())
            .flatten()
    })?;
    let sections =
        head.lines().filter(|l| l.starts_with("D:") && l.to_ascii_lowercase().contains("long section")).count();
    if sections < 2 || !(increment > 0.0) {
        return None;
    }
    // After the line that opens the $ROAD_CRG block (a line of its own: the words also occur in comments).
    let mut offset = 0;
    let mut line_end = None;
    for line in head.split_inclusive('\n') {
        offset += line.len();
        if line.trim().eq_ignore_ascii_case("$ROAD_CRG") {
            line_end = Some(offset);
            break;
        }
    }
    let line_end = line_end?;
    let insert = format!("LONG_SECTION_V_RIGHT = {}\n", -0.5 * (sections - 1) as f64 * increment);
    let mut out = Vec::with_capacity(bytes.len() + insert.len());
    out.extend_from_slice(&bytes[..line_end]);
    out.extend_from_slice(insert.as_bytes());
    out.extend_from_slice(&bytes[line_end..]);
    Some(out)
}

/// The number of cross sections the `$ROAD_CRG` header declares, when it gives the reference line's end:
/// round((END_U − START_U)/INCREMENT) + 1.
fn declared_cross_sections(bytes: &[u8]) -> Option<usize> {
    let head = &bytes[..bytes.len().min(64 << 10)];
    let text = String::from_utf8_lossy(head);
    let key = |k: &str| -> Option<f64> {
        text.lines().find_map(|l| {
            let (name, value) = l.split_once('=')?;
            name.trim().eq_ignore_ascii_case(k).then(|| value.trim().parse::<f64>().ok()).flatten()
        })
    };
    let (end, inc) = (key("REFERENCE_LINE_END_U")?, key("REFERENCE_LINE_INCREMENT")?);
    let start = key("REFERENCE_LINE_START_U").unwrap_or(0.0);
    let n = (end - start) / inc;
    (0.0..1e12).contains(&n).then(|| n.round() as usize + 1)
}

/// The data section as the header defines it: where it starts (the byte after the `$$$$` line), the
/// format code's value width and record size, and each channel (`D:` line) in order.
struct DataLayout {
    start: usize,
    ascii: bool,
    double: bool,
    width: usize,
    record: usize,
    channels: Vec<Channel>,
}

#[derive(Clone, Copy, PartialEq)]
enum Channel {
    /// A long section's heights, m (its number counting from 1 among the heights).
    Height(usize),
    /// A reference-line channel (phi, slope, banking) or one the reader ignores.
    Other,
}

/// The layout of the data section, read from the header as the `opencrg` crate reads it (sections open on a
/// line starting with `$`, a `$` line closes them, `$CT` blocks are comments); `None` when the file has no
/// `#:` format or no `$$$$` line (the crate's own errors then name what is missing).
fn data_layout(bytes: &[u8]) -> Option<DataLayout> {
    let (mut pos, mut section, mut format, mut channels) = (0, "", None::<String>, Vec::new());
    while pos < bytes.len() {
        let end = bytes[pos..].iter().position(|&b| b == b'\n' || b == b'\r').map_or(bytes.len(), |e| pos + e);
        let next = if bytes.get(end) == Some(&b'\r') && bytes.get(end + 1) == Some(&b'\n') { end + 2 } else { end + 1 };
        let line = String::from_utf8_lossy(&bytes[pos..end]);
        let tag = line.trim_start_matches(' ');
        pos = next;
        if section == "ct" {
            if line.starts_with('$') {
                section = "";
            }
            continue;
        }
        if tag.starts_with('$') {
            let upper = tag.to_ascii_uppercase();
            if upper.starts_with("$$$$") {
                let head = format?.to_ascii_uppercase();
                let (ascii, double, long) = (head.contains('F'), head.contains('D'), head.contains('L'));
                let width = match (ascii, double) {
                    (true, true) => 20,
                    (true, false) => 10,
                    (false, true) => 8,
                    (false, false) => 4,
                };
                let packed = width * channels.len();
                let record = if long { packed.div_ceil(80) * 80 } else { packed };
                return Some(DataLayout { start: pos.min(bytes.len()), ascii, double, width, record, channels });
            }
            section = if !section.is_empty() {
                ""
            } else if upper.starts_with("$CT") {
                "ct"
            } else if upper.starts_with("$KD_DEFINITION") {
                "kd"
            } else {
                "other"
            };
            continue;
        }
        if section == "kd" {
            let head = tag.get(..2).unwrap_or("").to_ascii_uppercase();
            if head == "#:" {
                format = Some(tag[2..].chars().take(4).collect());
            } else if head == "D:" {
                let heights = channels.iter().filter(|c| matches!(c, Channel::Height(_))).count();
                let is_height = tag.to_ascii_lowercase().contains("long section");
                channels.push(if is_height { Channel::Height(heights + 1) } else { Channel::Other });
            }
        }
    }
    None
}

/// Binary data (`#:KRBI`, `KDBI`, `LRBI`, `LDBI`: big-endian IEEE values, records packed or padded to 80
/// bytes) are checked before the crate reads them, which reads the records the header declares and
/// ignores what follows: the data must be whole records, as many as the header declares
/// (REFERENCE_LINE_START_U, END_U, INCREMENT), and every height finite (NaN marks a hole) within
/// ±`MAX_HEIGHT_M`. Each refusal names the byte offset in the file.
fn check_binary_data(name: &str, bytes: &[u8]) -> Result<(), String> {
    let Some(layout) = data_layout(bytes) else { return Ok(()) };
    if layout.ascii || layout.record == 0 {
        return Ok(());
    }
    let DataLayout { start, record, width, .. } = layout;
    let data = &bytes[start..];
    let what = format!(
        "records of {record} bytes ({} channels of {width}-byte values{})",
        layout.channels.len(),
        if record > width * layout.channels.len() { ", padded to 80 bytes" } else { "" }
    );
    // IPLOS writers (Chrono's, OpenCRG's) fill the data up to a whole 80-byte block with NaN values.
    let nan_fill = |tail: &[u8]| {
        tail.len() < 80
            && tail.chunks(width).all(|b| match b.len() {
                4 => f32::from_be_bytes(b.try_into().expect("4 bytes")).is_nan(),
                8 => f64::from_be_bytes(b.try_into().expect("8 bytes")).is_nan(),
                _ => false,
            })
    };
    let records = match declared_cross_sections(bytes) {
        Some(declared) => {
            let end = declared.saturating_mul(record);
            if data.len() < end || !nan_fill(&data[end..]) {
                return Err(format!(
                    "road file {name}: its binary data (from byte offset {start}, {} bytes) are not the {declared} \
                     {what} its header declares (REFERENCE_LINE_START_U, END_U, INCREMENT) and a NaN fill to an \
                     80-byte block: they hold {} whole records and {} bytes more, {}: truncated, damaged, or a \
                     wrong header",
                    data.len(),
                    data.len() / record,
                    data.len() % record,
                    if data.len() < end {
                        format!(
                            "and end at byte offset {} where the declared records would end at {}",
                            start + data.len(),
                            start + end
                        )
                    } else {
                        format!("the bytes from offset {} on are not a NaN fill", start + end)
                    }
                ));
            }
            declared
        }
        None => data.len() / record, // no END_U: the crate's error names it
    };
    let data = &data[..records * record];
    for (r, chunk) in data.chunks_exact(record).enumerate() {
        for (c, channel) in layout.channels.iter().enumerate() {
            let b = &chunk[c * width..(c + 1) * width];
            let value = if layout.double {
                f64::from_be_bytes(b.try_into().expect("8 bytes"))
            } else {
                f64::from(f32::from_be_bytes(b.try_into().expect("4 bytes")))
            };
            let Channel::Height(k) = *channel else {
                // phi (rad), slope and banking (m/m): a finite value of that size, or a damaged one.
                if !(value.is_nan() || value.abs() <= MAX_HEIGHT_M) {
                    return Err(format!(
                        "road file {name}: the value {value:.3e} of channel {} at byte offset {} (cross section {}) \
                         is beyond ±{MAX_HEIGHT_M}: a damaged file",
                        c + 1,
                        start + r * record + c * width,
                        r + 1
                    ));
                }
                continue;
            };
            if !(value.is_nan() || value.abs() <= MAX_HEIGHT_M) {
                return Err(format!(
                    "road file {name}: the height {value:.3e} m at byte offset {} (cross section {}, long section \
                     {k}) is beyond ±{MAX_HEIGHT_M} m: a damaged file, or not heights in metres",
                    start + r * record + c * width,
                    r + 1
                ));
            }
        }
    }
    Ok(())
}

/// The loaded surface, with the header's start height, slope, banking and modifiers applied: every grid
/// value and the surface along the grid's edges and reference line within ±`MAX_HEIGHT_M`.
fn check_heights(name: &str, grid: &CrgGrid) -> Result<(), String> {
    let (nu, nv) = grid.dims();
    let shift = grid.z_shift();
    if let Some(i) = grid.z_values().iter().position(|&z| !(z.is_nan() || (f64::from(z) + shift).abs() <= MAX_HEIGHT_M))
    {
        return Err(format!(
            "road file {name}: the grid height {:.3e} m (cross section {}, long section {}) is beyond ±{MAX_HEIGHT_M} m",
            f64::from(grid.z_values()[i]) + shift,
            i / nv + 1,
            i % nv + 1
        ));
    }
    let ([u0, u1], [v0, v1]) = (range(grid.u_range()), range(grid.v_range()));
    // At most 20 000 cross sections (a load-time cost of milliseconds); a height the reference line's slope
    // raises stays raised beyond it, so a sample after it sees it.
    let stride = nu.div_ceil(20_000).max(1);
    for iu in (0..nu).step_by(stride).chain([nu - 1]) {
        let u = u0 + (u1 - u0) * iu as f64 / (nu - 1).max(1) as f64;
        for v in [v0, 0.0_f64.clamp(v0, v1), v1] {
            if let Some(z) = grid.elevation_at_uv(Uv { u, v }) {
                if !(z.is_nan() || z.abs() <= MAX_HEIGHT_M) {
                    return Err(format!(
                        "road file {name}: the surface at u = {u} m, v = {v} m is {z:.3e} m high, beyond \
                         ±{MAX_HEIGHT_M} m (the header's start height, slope or banking, or its modifiers)"
                    ));
                }
            }
        }
    }
    Ok(())
}

/// ASCII data (`#:LRFI`) are fixed fields of 10 characters: each must be a number (NaN marks a hole) or
/// an IPLOS marker (`**unused**`, `*missing*`), and no field may be cut short. The crate would read text as a hole.
fn check_ascii_data(name: &str, bytes: &[u8]) -> Result<(), String> {
    let text = String::from_utf8_lossy(&bytes[..bytes.len().min(64 << 10)]);
    if !text.lines().any(|l| l.trim().to_ascii_uppercase().starts_with("#:LRFI")) {
        return Ok(()); // binary data, or no format line: the crate's checks
    }
    let Ok(all) = std::str::from_utf8(bytes) else {
        return Err(format!("road file {name}: an ASCII (#:LRFI) file that is not text"));
    };
    // Each line with the byte offset it starts at.
    let mut offset = 0;
    let mut lines = all.split_inclusive('\n').enumerate().map(|(i, l)| {
        offset += l.len();
        (i, offset - l.len(), l.trim_end_matches(['\n', '\r']))
    });
    // The data start after the line of `$` that closes the last block.
    let mut start = None;
    for (i, _, l) in lines.by_ref() {
        if l.trim_start().starts_with("$$$$") {
            start = Some(i);
            break;
        }
    }
    let Some(_) = start else { return Ok(()) };
    for (i, at, line) in lines {
        let line = line.trim_end();
        if line.is_empty() || line.starts_with('*') {
            continue;
        }
        let chars: Vec<char> = line.chars().collect();
        if !chars.len().is_multiple_of(10) && chars.len() % 10 < 7 {
            // Fields are right-aligned in 10 characters; a last field shorter than its width is cut.
            return Err(format!(
                "road file {name}, line {}: a record of {} characters is not whole 10-character fields",
                i + 1,
                chars.len()
            ));
        }
        // A record may wrap over several lines (eight fields to an 80-column line); `**unused**` fills a
        // virtual channel's field and `*missing*` marks a hole (IPLOS markers).
        for (k, field) in chars.chunks(10).enumerate() {
            let f: String = field.iter().collect();
            let f = f.trim();
            let marker = f.len() > 2 && f.starts_with('*') && f.ends_with('*'); // *missing*, **unused**
            if marker {
                continue;
            }
            let Ok(value) = f.parse::<f64>() else {
                return Err(format!("road file {name}, line {}, value {}: {f:?} is not a number", i + 1, k + 1));
            };
            // Heights in m, phi in rad, slope and banking in m/m: beyond ±1 km none is a road's.
            if !(value.is_nan() || value.abs() <= MAX_HEIGHT_M) {
                let byte = at + field_start(line, k);
                return Err(format!(
                    "road file {name}, line {}, value {} (byte offset {byte}): {value:.3e} is beyond ±{MAX_HEIGHT_M} \
                     (m for heights): a damaged file, or not heights in metres",
                    i + 1,
                    k + 1
                ));
            }
        }
    }
    Ok(())
}

/// The byte offset within `line` of its `k`-th 10-character field.
fn field_start(line: &str, k: usize) -> usize {
    line.char_indices().nth(10 * k).map_or(line.len(), |(b, _)| b)
}

fn range((a, b): (f64, f64)) -> [f64; 2] {
    [a, b]
}

/// A file's identity: its canonical path (with a selector, such as an OpenDRIVE road id), length and
/// modification time.
type FileKey = (PathBuf, String, u64, Option<std::time::SystemTime>);

/// Files loaded in this process: large files are read once and shared by every FMU instance (and run) that
/// names them (same path, length and modification time). One cache per file type.
pub(crate) struct SharedFiles<T>(Mutex<Option<HashMap<FileKey, Weak<T>>>>);

impl<T> SharedFiles<T> {
    pub(crate) const fn new() -> Self {
        SharedFiles(Mutex::new(None))
    }

    /// The copy of `path` (with `selector`) already loaded, or `read()`'s, kept while anything holds it.
    pub(crate) fn get(
        &self,
        path: &Path,
        selector: &str,
        read: impl FnOnce() -> Result<T, String>,
    ) -> Result<Arc<T>, String> {
        let meta = std::fs::metadata(path).map_err(|e| format!("cannot read the road file {}: {e}", path.display()))?;
        let canonical = path.canonicalize().unwrap_or_else(|_| path.to_path_buf());
        let key = (canonical, selector.to_string(), meta.len(), meta.modified().ok());
        // A poisoned lock only means another thread panicked while holding it: the map is still usable.
        let mut guard = self.0.lock().unwrap_or_else(|p| p.into_inner());
        let map = guard.get_or_insert_with(HashMap::new);
        map.retain(|_, w| w.strong_count() > 0);
        if let Some(s) = map.get(&key).and_then(Weak::upgrade) {
            return Ok(s);
        }
        let loaded = Arc::new(read()?);
        map.insert(key, Arc::downgrade(&loaded));
        Ok(loaded)
    }
}

static LOADED: SharedFiles<Surface> = SharedFiles::new();

/// Loads a CRG file, or returns the copy already loaded.
pub fn load(path: &Path) -> Result<Arc<Surface>, String> {
    LOADED.get(path, "", || Surface::read(path))
}

/// The surface a road specification names: an OpenCRG file, or `iso8608:CLASS:SEED[:LENGTH_M[:DX_M]]`
/// (`road::iso8608`), generated and read as a CRG grid.
pub fn surface_for(spec: &str) -> Result<Arc<Surface>, String> {
    match super::iso8608::Iso8608::parse(spec) {
        Some(iso) => Ok(Arc::new(Surface::from_bytes(spec, iso?.crg_text().as_bytes())?)),
        None => load(Path::new(spec)),
    }
}

/// A surface placed in the simulation's ground frame: ground (x, y) ↦ road (x, y) = origin + R(heading)
/// ((x, y) − anchor).
#[derive(Debug, Clone)]
pub struct PlacedSurface {
    pub surface: Arc<Surface>,
    /// The reference line's start (u at its start, v = 0) at the anchor, heading along ground x.
    pub placement: Placement,
    /// A straight reference line (one heading from start to end, as the NRMM courses and the ISO 8608
    /// roads have): u and v are then projections, without the crate's search along the line.
    straight: Option<f64>,
}

impl PartialEq for PlacedSurface {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.surface, &other.surface) && self.placement.anchor == other.placement.anchor
    }
}

impl PlacedSurface {
    /// The surface with its reference line's start at ground point `anchor`, heading along ground x.
    pub fn new(surface: Arc<Surface>, anchor: [f64; 2]) -> PlacedSurface {
        let (u0, _) = surface.grid.u_range();
        let start = Uv { u: u0, v: 0.0 };
        let origin = surface.grid.xy_from_uv(start);
        let phi = surface.grid.heading_at_uv(start).phi;
        let (_, u1) = surface.grid.u_range();
        let end = surface.grid.xy_from_uv(Uv { u: u1, v: 0.0 });
        // Straight when the end lies on the start's heading, to 1e-9 of the length.
        let along = (end.x - origin.x) * phi.cos() + (end.y - origin.y) * phi.sin();
        let across = -(end.x - origin.x) * phi.sin() + (end.y - origin.y) * phi.cos();
        let end_phi = surface.grid.heading_at_uv(Uv { u: u1, v: 0.0 }).phi;
        let straight = (across.abs() <= 1e-9 * (u1 - u0).abs().max(1.0)
            && (along - (u1 - u0)).abs() <= 1e-9 * (u1 - u0).abs().max(1.0)
            && (end_phi - phi).abs() < 1e-12)
            .then_some(u0);
        let placement = Placement { anchor, origin: [origin.x, origin.y], cos: phi.cos(), sin: phi.sin() };
        PlacedSurface { surface, placement, straight }
    }

    /// The road's x, y of a ground point.
    fn road_xy(&self, x: f64, y: f64) -> Xy {
        let [x, y] = self.placement.to_file(x, y);
        Xy { x, y }
    }

    /// The grid position of a ground point, if the reference line has one for it. On a straight reference
    /// line the ground's axes are the road's (the placement turns one into the other): u and v are the
    /// offsets from the anchor.
    fn uv(&self, x: f64, y: f64) -> Option<Uv> {
        match self.straight {
            Some(u0) => Some(Uv { u: u0 + (x - self.placement.anchor[0]), v: y - self.placement.anchor[1] }),
            None => self.surface.grid.uv_from_xy(self.road_xy(x, y)),
        }
    }

    /// Whether the surface is an ISO 8608 road (written by this model), not a road file.
    pub fn is_generated(&self) -> bool {
        self.surface.name.starts_with("iso8608:")
    }

    /// The grid position of a ground point with u in the grid's range or, on a closed line, in
    /// [u1, u0 + lap) (the gap bridged from the last cross section to the first).
    fn wrapped_uv(&self, x: f64, y: f64) -> Option<Uv> {
        let mut uv = self.uv(x, y)?;
        if let Some(c) = self.surface.closed {
            let (u0, _) = self.surface.grid.u_range();
            uv.u = u0 + (uv.u - u0).rem_euclid(c.lap);
        }
        Some(uv)
    }

    /// Whether the ground point lies on the grid (u and v within their ranges; u anywhere on a closed line).
    pub fn inside(&self, x: f64, y: f64) -> bool {
        let ([u0, u1], [v0, v1]) = self.surface.extent();
        let u1 = self.surface.closed.map_or(u1, |c| u0 + c.lap);
        self.wrapped_uv(x, y).is_some_and(|uv| uv.u >= u0 && uv.u <= u1 && uv.v >= v0 && uv.v <= v1)
    }

    /// `None` where the road has a surface: within the grid, beyond it where the file's border mode
    /// continues it, anywhere along a closed line. Else the position and the extent (`Road::off_road`).
    /// Asked only once a height is NaN (the contact's check), so it costs nothing per evaluation.
    pub fn off_road(&self, x: f64, y: f64) -> Option<String> {
        let s = &*self.surface;
        if s.open == [true, true] {
            return None;
        }
        let ([u0, u1], [v0, v1]) = s.extent();
        let Some(uv) = self.wrapped_uv(x, y) else {
            return Some(format!(
                "at x = {x:.2} m, y = {y:.2} m the road file {} has no position along its reference line",
                s.name
            ));
        };
        let beyond_u = s.closed.is_none() && !s.open[0] && !(u0..=u1).contains(&uv.u);
        let beyond_v = !s.open[1] && !(v0..=v1).contains(&uv.v);
        (beyond_u || beyond_v).then(|| {
            let along = match s.closed {
                Some(c) => format!("u wraps, a closed reference line of {:.2} m a lap", c.lap),
                None => format!("u {u0}..{u1} m"),
            };
            format!(
                "at x = {x:.2} m, y = {y:.2} m (u = {:.2} m, v = {:.2} m) it is beyond the road file {}, whose \
                 extent is {along}, v {v0}..{v1} m, and which declares no border mode that continues its surface \
                 there (BORDER_MODE_U/V in $ROAD_CRG_OPTS; docs/roads.md, \"The road's edge\")",
                uv.u, uv.v, s.name
            )
        })
    }

    /// The height and its slopes in the road's axes at a grid position (u wrapped), `None` where the grid
    /// has no surface. In a closed line's gap, the last cross section and the first blended linearly.
    fn surface_at(&self, uv: Uv) -> Option<(f64, [f64; 2])> {
        let grid = &self.surface.grid;
        let at = |uv: Uv| -> Option<(f64, [f64; 2])> {
            let (z, n) = (grid.elevation_at_uv(uv)?, grid.normal_at_uv(uv)?);
            (n.z > 0.0).then(|| (z, [-n.x / n.z, -n.y / n.z]))
        };
        let (u0, u1) = grid.u_range();
        match self.surface.closed {
            Some(c) if uv.u > u1 => {
                let t = ((uv.u - u1) / c.gap).min(1.0);
                let (za, ga) = at(Uv { u: u1, ..uv })?;
                let (zb, gb) = at(Uv { u: u0, ..uv })?;
                // Along the gap (from the end's point to the start's) the blend's slope; across it the
                // end's and the start's lateral slopes, blended.
                let (end, start) = (grid.xy_from_uv(Uv { u: u1, ..uv }), grid.xy_from_uv(Uv { u: u0, ..uv }));
                let (dx, dy) = (start.x - end.x, start.y - end.y);
                let length = dx.hypot(dy);
                let d = [dx / length, dy / length];
                let l = [-d[1], d[0]];
                let along = (zb - za) / length;
                let across = (1.0 - t) * (ga[0] * l[0] + ga[1] * l[1]) + t * (gb[0] * l[0] + gb[1] * l[1]);
                Some((za + t * (zb - za), [along * d[0] + across * l[0], along * d[1] + across * l[1]]))
            }
            _ => at(uv),
        }
    }
}

impl Road for PlacedSurface {
    /// The crate's elevation and its surface normal, the normal's slopes turned back into the ground frame;
    /// NaN where there is no surface (`off_road` says why).
    fn height_and_gradient(&self, x: f64, y: f64) -> (f64, [f64; 2]) {
        match self.wrapped_uv(x, y).and_then(|uv| self.surface_at(uv)) {
            Some((z, gradient)) => (z, self.placement.gradient_to_ground(gradient)),
            None => (f64::NAN, [f64::NAN; 2]),
        }
    }
}

impl FileRoad for PlacedSurface {
    fn name(&self) -> &str {
        &self.surface.name
    }

    fn inside(&self, x: f64, y: f64) -> bool {
        PlacedSurface::inside(self, x, y)
    }
}

/// The border modes a surface may declare, as `opencrg` names them (for docs and messages).
pub fn border_mode_name(mode: BorderMode) -> &'static str {
    match mode {
        BorderMode::None => "none (no surface beyond the grid)",
        BorderMode::Zero => "zero",
        BorderMode::Keep => "keep (the edge value continues)",
        BorderMode::Repeat => "repeat",
        BorderMode::Reflect => "reflect",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Three cross sections 1 m apart, long sections at v = −1, 0, 1 m: a 0.1 m ridge along u = 1 m.
    pub(super) const SMALL: &[u8] = b"$ROAD_CRG
REFERENCE_LINE_INCREMENT = 1.0
LONG_SECTION_V_RIGHT = -1.0
LONG_SECTION_V_INCREMENT = 1.0
$
$KD_Definition
#:LRFI
D:long section 1,m
D:long section 2,m
D:long section 3,m
$
$$$$
 0.0000000 0.0000000 0.0000000
 0.1000000 0.1000000 0.1000000
 0.0000000 0.0000000 0.0000000
";

    #[test]
    fn placed_heights_and_slopes() {
        let s = Arc::new(Surface::from_bytes("small.crg", SMALL).unwrap());
        let p = PlacedSurface::new(s, [5.0, 0.0]);
        // Ground x = 5 is u = 0; x = 5.5 is halfway up the ridge, slope +0.1 per m along x. The crate stores
        // the grid in f32 (0.1 is 0.10000000149): 1e-8 covers it.
        let (h, [hx, hy]) = p.height_and_gradient(5.5, 0.3);
        assert!((h - 0.05).abs() < 1e-8 && (hx - 0.1).abs() < 1e-8 && hy.abs() < 1e-12, "{h} {hx} {hy}");
        let (h, [hx, _]) = p.height_and_gradient(6.5, -0.2);
        assert!((h - 0.05).abs() < 1e-8 && (hx + 0.1).abs() < 1e-8);
        assert!(p.inside(6.0, 0.9) && !p.inside(8.0, 0.0) && !p.inside(6.0, 1.5));
        // No border mode declared: no surface beyond the grid, and what the wheel left is named.
        assert!(p.height_and_gradient(20.0, 0.0).0.is_nan());
        let off = p.off_road(20.0, 0.0).unwrap();
        assert!(off.contains("x = 20.00 m") && off.contains("u = 15.00 m") && off.contains("u 0..2 m"), "{off}");
        assert!(p.off_road(6.0, 0.5).is_none() && p.off_road(6.0, 1.2).unwrap().contains("v = 1.20 m"));
        // Border modes the file declares: keep along u continues the edge; v still has none.
        let kept = String::from_utf8(SMALL.to_vec())
            .unwrap()
            .replace("$KD_Definition", "$ROAD_CRG_OPTS\nBORDER_MODE_U = 2\n$\n$KD_Definition");
        let p = PlacedSurface::new(Arc::new(Surface::from_bytes("kept.crg", kept.as_bytes()).unwrap()), [5.0, 0.0]);
        assert_eq!(p.height_and_gradient(20.0, 0.0).0, 0.0);
        assert!(p.off_road(20.0, 0.0).is_none() && p.off_road(20.0, 1.2).is_some());
    }

    /// Chrono's 4 in half-round (binary, `#:KRBI`: 10 001 records of three f32 heights) and where its data
    /// start.
    fn halfround() -> (Vec<u8>, usize) {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/data/chrono/terrain/crg_roads/halfround_4in.crg");
        let bytes = std::fs::read(path).unwrap();
        let start = data_layout(&bytes).unwrap().start;
        (bytes, start)
    }

    /// One test per kind of damage: each is refused with its cause and the byte offset (computed here from
    /// the layout: 12-byte records from the data's start).
    #[test]
    fn damaged_binary_files_are_refused_with_the_cause_and_the_offset() {
        let (good, start) = halfround();
        // 10 001 records of 12 bytes, and 68 bytes of NaN fill to a whole 80-byte block.
        let end = start + 10_001 * 12;
        assert_eq!((good.len() - start) % 80, 0, "the file's data are whole 80-byte blocks");
        assert!(Surface::from_bytes("whole.crg", &good).is_ok());
        let refused = |name: &str, bytes: &[u8], words: &[&str]| {
            let e = Surface::from_bytes(name, bytes).unwrap_err();
            for w in words.iter().chain(&[name]) {
                assert!(e.contains(w), "{name}: {w:?} not in {e}");
            }
        };
        // Cut inside a record (7 bytes short of the declared records): the partial record is named.
        refused(
            "cut.crg",
            &good[..end - 7],
            &["10000 whole records and 5 bytes more", &format!("byte offset {}", end - 7)],
        );
        // One whole record fewer, and one more (in place of the fill) than the header declares.
        refused("fewer.crg", &good[..end - 12], &["10000 whole records", &format!("would end at {end}")]);
        let more = [&good[..end], &good[end - 12..end]].concat();
        refused("more.crg", &more, &["10002 whole records", &format!("from offset {end} on are not a NaN fill")]);
        // A header whose end disagrees with the data.
        let text = String::from_utf8_lossy(&good[..start]).into_owned();
        let header = text.replacen("1.0000000000000000e+02", "1.0100000000000000e+02", 1);
        let bytes = [header.as_bytes(), &good[start..]].concat();
        refused("header.crg", &bytes, &["not the 10101 records", "would end at"]);
        // A height of 1.1e38 m (the damaged ASAM file's value) in record 5000, long section 2.
        let mut big = good.clone();
        let at = start + 4999 * 12 + 4;
        big[at..at + 4].copy_from_slice(&1.1e38f32.to_be_bytes());
        refused("big.crg", &big, &[&format!("byte offset {at}"), "cross section 5000, long section 2", "1.100e38"]);
        // An infinite height.
        big[at..at + 4].copy_from_slice(&f32::INFINITY.to_be_bytes());
        refused("inf.crg", &big, &[&format!("byte offset {at}"), "inf"]);
        // 1001 m is beyond the bound, 999 m is not.
        big[at..at + 4].copy_from_slice(&1001f32.to_be_bytes());
        refused("km.crg", &big, &[&format!("byte offset {at}"), "±1000 m"]);
        big[at..at + 4].copy_from_slice(&999f32.to_be_bytes());
        assert!(Surface::from_bytes("999.crg", &big).is_ok());
        // A modifier that puts the surface 2 km up (the reference point's height; without a modifier block
        // OpenCRG puts the reference line's start at z = 0).
        let bytes = [b"$ROAD_CRG_MODS\nrefpoint_z = 2000\n$\n", &good[..]].concat();
        refused("high.crg", &bytes, &["2.000e3 m high", "beyond ±1000 m"]);
    }

    #[test]
    fn ascii_heights_beyond_a_kilometre_are_refused_with_the_offset() {
        let text = String::from_utf8(SMALL.to_vec()).unwrap();
        let bad = text.replace(" 0.1000000 0.1000000 0.1000000", " 0.10000001.2000e+38 0.1000000");
        let at = bad.find("1.2000e+38").unwrap(); // the second field of the second record
        let e = Surface::from_bytes("ascii.crg", bad.as_bytes()).unwrap_err();
        assert!(
            e.contains(&format!("byte offset {at}")) && e.contains("line 14, value 2") && e.contains("1.200e38"),
            "{e}"
        );
    }

    #[test]
    fn bad_files_are_named_errors() {
        let text = String::from_utf8(SMALL.to_vec()).unwrap();
        for (name, body) in [
            ("zero.crg", text.replace("REFERENCE_LINE_INCREMENT = 1.0", "REFERENCE_LINE_INCREMENT = 0.0")),
            ("text.crg", text.replace(" 0.1000000 0.1000000", " 0.1000000 abc")),
            ("cut.crg", text[..text.len() - 40].to_string()),
            ("empty.crg", String::new()),
        ] {
            let e = Surface::from_bytes(name, body.as_bytes()).unwrap_err();
            assert!(e.contains(name), "{name}: {e}");
        }
    }
}
#[cfg(test)]
mod closed_tests {
    use super::*;

    fn circle() -> Arc<Surface> {
        load(Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/data/roads/circle_50m.crg"))).unwrap()
    }

    /// The 50 m circle (`data/roads/circle_50m.crg`, `scripts/make_circle_crg.py`): its last cross section
    /// lies one increment (0.2 m) before its first, and it asks for the closed track (REFLINE_CONTINUATION =
    /// 1). Placed at the origin heading along x (the file's own frame): the crate's grid points come back at
    /// their (u, v), those of a second lap at u − lap.
    #[test]
    fn a_closed_reference_line_is_lapped() {
        let s = circle();
        let lap = s.lap().expect("closed");
        assert!((lap - 314.0).abs() < 1e-6, "{lap}"); // 313.8 m of cross sections and the 0.2 m gap
        let p = PlacedSurface::new(s.clone(), [0.0, 0.0]);
        assert_eq!(p.placement, Placement { anchor: [0.0; 2], origin: [0.0; 2], cos: 1.0, sin: 0.0 });
        for u in [0.1, 50.3, 157.0, 300.0, 313.7] {
            for v in [-5.5, 0.0, 4.0] {
                let xy = s.grid.xy_from_uv(Uv { u, v });
                // The search's answer to 1e-9 m (it inverts the same polygon).
                let uv = p.wrapped_uv(xy.x, xy.y).unwrap();
                assert!((uv.u - u).abs() < 1e-9 && (uv.v - v).abs() < 1e-9, "({u}, {v}): {uv:?}");
                assert_eq!(p.height_and_gradient(xy.x, xy.y), (0.0, [0.0, 0.0]), "a level track");
                assert!(p.off_road(xy.x, xy.y).is_none() && p.inside(xy.x, xy.y));
            }
        }
        // Behind the start is the end of the lap (u wraps), in the gap too; off the track's 12 m is named.
        let behind = p.wrapped_uv(-5.0, 0.25).unwrap();
        assert!((behind.u - (lap - 5.0)).abs() < 0.02, "{behind:?}");
        assert_eq!(p.height_and_gradient(-0.1, 0.0), (0.0, [0.0, 0.0]));
        let off = p.off_road(30.0, 0.0).unwrap();
        // v = R − |(30, 0) − (0, R)| = −8.31 m on the circle of R = 314/(2π); −8.36 m on the file's polygon.
        assert!(off.contains("x = 30.00 m") && off.contains("v = -8.36 m") && off.contains("314.00 m a lap"), "{off}");
        assert!(p.height_and_gradient(30.0, 0.0).0.is_nan());
    }

    /// `$ROAD_CRG_FILE` includes are read relative to the including file's folder, checked as the including
    /// file is; the including file's options apply (here a border mode). A missing or damaged include is
    /// refused naming it.
    #[test]
    fn includes_are_read_relative_to_the_including_file() {
        let dir = std::env::temp_dir().join(format!("rtv_crg_include_{}", std::process::id()));
        std::fs::create_dir_all(dir.join("data")).unwrap();
        std::fs::write(dir.join("data/small.crg"), super::tests::SMALL).unwrap();
        let wrapper = "$ROAD_CRG_FILE\ndata/small.crg\n$\n$ROAD_CRG_OPTS\nBORDER_MODE_U = 2\n$\n";
        std::fs::write(dir.join("road.crg"), wrapper).unwrap();
        let direct =
            PlacedSurface::new(Arc::new(Surface::from_bytes("small.crg", super::tests::SMALL).unwrap()), [0.0; 2]);
        let included = PlacedSurface::new(load(&dir.join("road.crg")).unwrap(), [0.0; 2]);
        for (x, y) in [(0.5, 0.3), (1.0, -0.9), (1.7, 0.0)] {
            assert_eq!(included.height_and_gradient(x, y), direct.height_and_gradient(x, y), "({x}, {y})");
        }
        // The wrapper's border mode: u continues (keep), the file alone has none.
        assert!(included.off_road(5.0, 0.0).is_none() && direct.off_road(5.0, 0.0).is_some());
        // Not from bytes (no folder), a missing include, a damaged one: named.
        let e = Surface::from_bytes("road.crg", wrapper.as_bytes()).unwrap_err();
        assert!(e.contains("road.crg") && e.contains("folder"), "{e}");
        std::fs::write(dir.join("missing.crg"), "$ROAD_CRG_FILE\ndata/none.crg\n$\n").unwrap();
        let e = load(&dir.join("missing.crg")).unwrap_err();
        assert!(e.contains("none.crg"), "{e}");
        let damaged = String::from_utf8(super::tests::SMALL.to_vec())
            .unwrap()
            .replace(" 0.1000000 0.1000000", " 0.1000000 abcdefghi");
        std::fs::write(dir.join("data/damaged.crg"), damaged).unwrap();
        std::fs::write(dir.join("damaged.crg"), "$ROAD_CRG_FILE\ndata/damaged.crg\n$\n").unwrap();
        let e = load(&dir.join("damaged.crg")).unwrap_err();
        assert!(e.contains("data/damaged.crg") && e.contains("not a number"), "{e}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// A track that asks for the closed continuation and does not close is refused by name.
    #[test]
    fn a_continuation_on_an_open_line_is_refused() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/data/chrono/terrain/crg_roads/handmade_straight.crg");
        let text = std::fs::read_to_string(path).unwrap();
        let asked = text.replacen("$KD_Definition", "$ROAD_CRG_OPTS\nREFLINE_CONTINUATION = 1\n$\n$KD_Definition", 1);
        assert_ne!(asked, text);
        let e = Surface::from_bytes("open.crg", asked.as_bytes()).unwrap_err();
        assert!(e.contains("open.crg") && e.contains("does not end where it starts"), "{e}");
    }
}
