//! How flag values are read (clap's value parsers; each error says what the value should be)
//! and how vectors are written back into messages.

use ellipsoid_splat::Intrinsics;
use glam::{DVec2, DVec3};

use super::render::MAX_IMAGE_SIDE;

/// `NAME=COLUMN,...` of `--columns`: each standard name once, neither side empty. Column names
/// may hold brackets but no commas (LAMMPS names never do).
pub(crate) fn parse_columns(text: &str) -> std::result::Result<Vec<(String, String)>, String> {
    let mut pairs: Vec<(String, String)> = Vec::new();
    for item in text.split(',') {
        let (name, column) = item
            .split_once('=')
            .map(|(n, c)| (n.trim(), c.trim()))
            .filter(|(n, c)| !n.is_empty() && !c.is_empty())
            .ok_or_else(|| format!("'{item}' is not NAME=COLUMN (e.g. shapex=c_shape[1])"))?;
        if pairs.iter().any(|(n, _)| n == name) {
            return Err(format!("{name} is mapped twice"));
        }
        pairs.push((name.to_string(), column.to_string()));
    }
    Ok(pairs)
}

/// `r,g,b;r,g,b;...` of `--type-colors`, each component a number in [0, 1].
pub(crate) fn parse_type_colors(text: &str) -> std::result::Result<Vec<[f32; 3]>, String> {
    text.split(';')
        .enumerate()
        .map(|(k, item)| {
            let [r, g, b] = parse_numbers::<3>(item, &format!("type {}'s colour as r,g,b", k + 1))?;
            let rgb = [r, g, b];
            if rgb.iter().any(|c| !(0.0..=1.0).contains(c)) {
                return Err(format!(
                    "type {}'s colour {item} has a component outside [0, 1]",
                    k + 1
                ));
            }
            Ok(rgb.map(|c| c as f32))
        })
        .collect()
}

/// A number flag's value. Such flags take values that start with `-`, so a flag given
/// where the value should be is reported as the missing value it is.
pub(crate) fn parse_number(text: &str) -> std::result::Result<f64, String> {
    text.trim().parse::<f64>().map_err(|_| {
        if text.starts_with("--") {
            format!("'{text}' is a flag, not a number: the value is missing")
        } else {
            format!("'{text}' is not a number")
        }
    })
}

/// `count` comma-separated finite numbers, named by `what`.
pub(crate) fn parse_numbers<const N: usize>(
    text: &str,
    what: &str,
) -> std::result::Result<[f64; N], String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if parts.len() != N {
        return Err(format!("expected {what}, got '{text}'"));
    }
    let mut v = [0.0; N];
    for (slot, part) in v.iter_mut().zip(&parts) {
        *slot = part
            .parse::<f64>()
            .map_err(|_| format!("'{part}' is not a number"))?;
        if !slot.is_finite() {
            return Err(format!("'{part}' is not finite"));
        }
    }
    Ok(v)
}

pub(crate) fn parse_intrinsics(text: &str) -> std::result::Result<Intrinsics, String> {
    let [fx, fy, cx, cy] = parse_numbers(text, "fx,fy,cx,cy")?;
    if !(fx > 0.0 && fy > 0.0) {
        return Err(format!(
            "the focal lengths fx and fy must be positive, got {fx} and {fy}"
        ));
    }
    Ok(Intrinsics { fx, fy, cx, cy })
}

pub(crate) fn parse_vec2(text: &str) -> std::result::Result<DVec2, String> {
    parse_numbers(text, "dx,dy").map(DVec2::from_array)
}

pub(crate) fn parse_viewport(text: &str) -> std::result::Result<[u32; 4], String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if parts.len() != 4 {
        return Err(format!("expected x,y,w,h in whole pixels, got '{text}'"));
    }
    let mut v = [0u32; 4];
    for (slot, part) in v.iter_mut().zip(&parts) {
        *slot = part
            .parse::<u32>()
            .map_err(|_| format!("'{part}' is not a whole number of pixels"))?;
    }
    if v[2] == 0 || v[3] == 0 {
        return Err(format!("the rectangle {}x{} is empty", v[2], v[3]));
    }
    Ok(v)
}

pub(crate) fn parse_pixels(text: &str) -> std::result::Result<u32, String> {
    text.trim()
        .parse::<u32>()
        .map_err(|_| format!("'{text}' is not a whole number of pixels (1 to {MAX_IMAGE_SIDE})"))
}

pub(crate) fn parse_orbit_degrees(text: &str) -> std::result::Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(degrees) if (0.01..=90.0).contains(&degrees.abs()) => Ok(degrees),
        _ => Err(format!(
            "'{text}' is not an orbit step in degrees per frame (0.01 to 90, either sign)"
        )),
    }
}

pub(crate) fn parse_samples(text: &str) -> std::result::Result<u32, String> {
    text.trim().parse::<u32>().map_err(|_| {
        format!(
            "'{text}' is not a whole number of samples per side (1 to {})",
            ellipsoid_splat::supersample::MAX_SUPERSAMPLE
        )
    })
}

pub(crate) fn parse_sample_count(text: &str) -> std::result::Result<u32, String> {
    text.trim()
        .parse::<u32>()
        .map_err(|_| format!("'{text}' is not a sample count (1, 2, 4, ... 64)"))
}

pub(crate) fn parse_vec3(text: &str) -> std::result::Result<DVec3, String> {
    parse_numbers(text, "x,y,z").map(DVec3::from_array)
}

/// `v` as the flags write it, `x,y,z`, each to four decimals without trailing zeros.
pub(crate) fn xyz(v: DVec3) -> String {
    v.to_array()
        .map(|x| {
            let text = format!("{x:.4}");
            let text = text.trim_end_matches('0').trim_end_matches('.');
            if text == "-0" {
                "0".to_string()
            } else {
                text.to_string()
            }
        })
        .join(",")
}
