//! Mitsuba's curve files (`linearcurve`, `bsplinecurve`): plain text, one control point a
//! line, `x y z radius`, a blank line between curves. Lines starting with `#` are comments.

/// The curves of a curve file, each a list of control points (x, y, z, radius).
pub fn read_curves(bytes: &[u8]) -> Result<Vec<Vec<[f32; 4]>>, String> {
    let text = std::str::from_utf8(bytes).map_err(|_| "a curve file is text; this is not UTF-8".to_string())?;
    let mut curves = Vec::new();
    let mut current: Vec<[f32; 4]> = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.starts_with('#') {
            continue;
        }
        if line.is_empty() {
            if !current.is_empty() {
                curves.push(std::mem::take(&mut current));
            }
            continue;
        }
        let numbers: Vec<&str> = line.split_whitespace().collect();
        let point = match numbers.as_slice() {
            [x, y, z, r] => [x, y, z, r].map(|n| n.parse::<f32>()),
            _ => {
                return Err(format!(
                    "line {}: expected four numbers, `x y z radius`, got {} field(s): `{line}`",
                    i + 1,
                    numbers.len()
                ))
            }
        };
        let mut values = [0.0f32; 4];
        for (value, parsed) in values.iter_mut().zip(point) {
            *value = parsed.map_err(|_| format!("line {}: `{line}` holds something other than four numbers", i + 1))?;
        }
        current.push(values);
    }
    if !current.is_empty() {
        curves.push(current);
    }
    if curves.is_empty() {
        return Err("the file holds no control points".into());
    }
    Ok(curves)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn curves_are_split_at_blank_lines() {
        let text = "\n# a comment\n0 0 0 1\n1 0 0 1\n\n\n2 0 0 0.5\n3 1 0 0.25\n4 1 1 0\n";
        let curves = read_curves(text.as_bytes()).unwrap();
        assert_eq!(curves.len(), 2);
        assert_eq!(curves[0], vec![[0.0, 0.0, 0.0, 1.0], [1.0, 0.0, 0.0, 1.0]]);
        assert_eq!(curves[1].len(), 3);
        assert_eq!(curves[1][2], [4.0, 1.0, 1.0, 0.0]);
    }

    #[test]
    fn bad_lines_are_named() {
        let error = read_curves(b"0 0 0 1\n1 0 0\n").unwrap_err();
        assert!(error.contains("line 2") && error.contains("four numbers"), "{error}");
        let error = read_curves(b"0 0 0 1\n1 0 x 1\n").unwrap_err();
        assert!(error.contains("line 2"), "{error}");
        assert!(read_curves(b"\n# nothing\n").is_err());
    }
}
