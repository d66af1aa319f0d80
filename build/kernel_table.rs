//! The kernel table (`kernels/launch.table`) and what build.rs generates from it: the CUDA
//! backend's launchers (`$OUT_DIR/launch.rs`, cudarc and host shim) and the shim's C++ launchers
//! (`$OUT_DIR/shim_exports.inc`). The table is the one place a kernel's arguments and launch shape
//! are written besides the kernel itself; the shim's C++ compile checks the two against each
//! other.

use std::fmt::Write as _;

/// One argument of a kernel.
pub struct Arg {
    pub name: String,
    pub ty: ArgType,
}

/// An argument's type (see the table's header).
#[derive(Clone, Copy, PartialEq)]
pub enum ArgType {
    Scalar(&'static str),
    Params,
    Grid,
    Buffer { element: &'static str, write: bool },
}

/// A table line: one kernel, or a family of entries of one signature chosen by index.
pub struct Entry {
    /// The method's name: the kernel's, or the family's.
    pub method: String,
    /// The kernels of `kernels/*.cu` it launches (one, or the family's in index order).
    pub kernels: Vec<String>,
    /// Thread count expression: an argument name, a literal, or `a/b` rounded up.
    pub threads: String,
    pub args: Vec<Arg>,
    /// A generated family (`body=NAME`): the device template every entry calls, and each
    /// entry's template arguments, in `kernels` order.
    pub body: Option<(String, Vec<String>)>,
}

/// The entries of a generated family `name{terms}{rotating}{phases}`: each placeholder in turn
/// (the first fastest) takes its values, giving the entry's name and template arguments:
/// `{terms}` the pair-term sets `_t0 .. _t(2^terms - 1)` (`u32` bits, `model::pair_terms`),
/// `{rotating}` none and `_r` (`bool`), `{phases}` none and `_mp` (`bool`, [HA06]).
fn expand(pattern: &str, pair_terms: usize) -> Vec<(String, String)> {
    let mut out = vec![(String::new(), Vec::<String>::new())];
    let mut rest = pattern;
    while let Some(open) = rest.find('{') {
        let close = rest[open..]
            .find('}')
            .map(|c| open + c)
            .unwrap_or_else(|| panic!("kernels/launch.table: unclosed `{{` in `{pattern}`"));
        let literal = &rest[..open];
        let values: Vec<(String, String)> = match &rest[open + 1..close] {
            "terms" => (0..1u32 << pair_terms)
                .map(|b| (format!("_t{b}"), format!("{b}u")))
                .collect(),
            "rotating" => vec![(String::new(), "false".into()), ("_r".into(), "true".into())],
            "phases" => vec![(String::new(), "false".into()), ("_mp".into(), "true".into())],
            other => panic!("kernels/launch.table: unknown placeholder `{{{other}}}`"),
        };
        // Earlier placeholders vary fastest: the new one is the outer loop.
        let mut next = Vec::new();
        for (suffix, arg) in &values {
            for (name, args) in &out {
                let mut args = args.clone();
                args.push(arg.clone());
                next.push((format!("{name}{literal}{suffix}"), args));
            }
        }
        out = next;
        rest = &rest[close + 1..];
    }
    out.into_iter()
        .map(|(name, args)| (format!("{name}{rest}"), args.join(", ")))
        .collect()
}

fn element(name: &str) -> &'static str {
    match name {
        "f32" => "f32",
        "u32" => "u32",
        "i32" => "i32",
        "f64" => "f64",
        "extremes" => "extremes",
        other => panic!("kernels/launch.table: unknown element type `{other}`"),
    }
}

fn arg_type(text: &str) -> ArgType {
    let text = text.trim();
    match text {
        "u32" => ArgType::Scalar("u32"),
        "i32" => ArgType::Scalar("i32"),
        "f32" => ArgType::Scalar("f32"),
        "params" => ArgType::Params,
        "grid" => ArgType::Grid,
        _ => {
            let (write, rest) = match text.strip_prefix("mut ") {
                Some(rest) => (true, rest.trim()),
                None => (false, text),
            };
            let inner = rest
                .strip_prefix('[')
                .and_then(|r| r.strip_suffix(']'))
                .unwrap_or_else(|| panic!("kernels/launch.table: unknown type `{text}`"));
            ArgType::Buffer {
                element: element(inner.trim()),
                write,
            }
        }
    }
}

/// Parses the table: `#` comments, lines continued while they start with white space;
/// `pair_terms` is the number of terms of `kernels/pair_terms.table` (`{terms}`).
pub fn parse(text: &str, pair_terms: usize) -> Vec<Entry> {
    let mut lines: Vec<String> = Vec::new();
    for line in text.lines() {
        let content = line.split('#').next().unwrap_or("");
        if content.trim().is_empty() {
            continue;
        }
        if content.starts_with(char::is_whitespace) {
            let last = lines
                .last_mut()
                .expect("kernels/launch.table: a continuation first");
            last.push(' ');
            last.push_str(content.trim());
        } else {
            lines.push(content.trim().to_string());
        }
    }
    lines.iter().map(|l| parse_line(l, pair_terms)).collect()
}

fn parse_line(line: &str, pair_terms: usize) -> Entry {
    let open = line
        .find('(')
        .unwrap_or_else(|| panic!("kernels/launch.table: no `(` in `{line}`"));
    let head = &line[..open];
    let args_text = line[open + 1..]
        .trim_end()
        .strip_suffix(')')
        .unwrap_or_else(|| panic!("kernels/launch.table: no closing `)` in `{line}`"));
    let args: Vec<Arg> = args_text
        .split(',')
        .map(|a| {
            let (name, ty) = a
                .split_once(':')
                .unwrap_or_else(|| panic!("kernels/launch.table: `{a}` has no type"));
            Arg {
                name: name.trim().to_string(),
                ty: arg_type(ty),
            }
        })
        .collect();
    let mut threads = None;
    let mut body_name = None;
    let mut words: Vec<&str> = Vec::new();
    for w in head.split_whitespace() {
        if let Some(expr) = w.strip_prefix("threads=") {
            threads = Some(expr.to_string());
        } else if let Some(name) = w.strip_prefix("body=") {
            body_name = Some(name.to_string());
        } else {
            words.push(w);
        }
    }
    let mut body = None;
    let (method, kernels) = match words.iter().position(|w| *w == "=") {
        Some(1) if words.len() == 3 && words[2].contains('{') => {
            let generated = expand(words[2], pair_terms);
            let name = body_name
                .take()
                .unwrap_or_else(|| panic!("kernels/launch.table: `{}` needs `body=`", words[0]));
            body = Some((name, generated.iter().map(|(_, a)| a.clone()).collect()));
            (
                words[0].to_string(),
                generated.into_iter().map(|(n, _)| n).collect(),
            )
        }
        Some(1) => (
            words[0].to_string(),
            words[2..].iter().map(|w| w.to_string()).collect(),
        ),
        Some(_) => panic!("kernels/launch.table: `family = entries` expected in `{line}`"),
        None => {
            assert!(
                words.len() == 1,
                "kernels/launch.table: one name expected in `{line}`"
            );
            (words[0].to_string(), vec![words[0].to_string()])
        }
    };
    let first = args
        .first()
        .map(|a| a.name.clone())
        .expect("a kernel has arguments");
    assert!(
        body_name.is_none(),
        "kernels/launch.table: `body=` is for a family with placeholders, in `{line}`"
    );
    Entry {
        method,
        kernels,
        threads: threads.unwrap_or(first),
        args,
        body,
    }
}

/// `$OUT_DIR/entries_<family>.cuh` for each generated family: one kernel per entry, calling
/// the family's device template with the entry's arguments (included at the end of the
/// family's `.cu`).
pub fn entries(entries: &[Entry]) -> Vec<(String, String)> {
    let mut files = Vec::new();
    for e in entries {
        let Some((body, templates)) = &e.body else {
            continue;
        };
        let mut s =
            String::from("// Generated by build.rs from kernels/launch.table; do not edit.\n#pragma once\n");
        let params: Vec<String> = e
            .args
            .iter()
            .map(|a| format!("{} {}", c_type(a.ty, true), a.name))
            .collect();
        let pass: Vec<&str> = e.args.iter().map(|a| a.name.as_str()).collect();
        for (k, t) in e.kernels.iter().zip(templates) {
            let _ = writeln!(
                s,
                "SPH_KERNEL({k})({}) {{\n    {body}<{t}>({});\n}}",
                params.join(", "),
                pass.join(", ")
            );
        }
        files.push((format!("entries_{}.cuh", e.method), s));
    }
    files
}

/// The thread count as Rust (`usize`).
fn threads_rust(expr: &str) -> String {
    if let Some((a, b)) = expr.split_once('/') {
        let b = if b.chars().all(|c| c.is_ascii_digit()) {
            b.to_string()
        } else {
            format!("{b} as usize")
        };
        format!("({a} as usize).div_ceil({b})")
    } else if expr.chars().all(|c| c.is_ascii_digit()) {
        format!("{expr}usize")
    } else {
        format!("{expr} as usize")
    }
}

/// The thread count as C (`u32`).
fn threads_c(expr: &str) -> String {
    // Argument names carry the launchers' `_` suffix.
    let c = |x: &str| {
        if x.chars().all(|c| c.is_ascii_digit()) {
            x.to_string()
        } else {
            format!("{x}_")
        }
    };
    if let Some((a, b)) = expr.split_once('/') {
        let (a, b) = (c(a), c(b));
        format!("(u32)(((unsigned long long)({a}) + ({b}) - 1u) / ({b}))")
    } else {
        c(expr)
    }
}

fn rust_element(e: &str) -> &'static str {
    match e {
        "f32" => "f32",
        "u32" => "u32",
        "i32" => "i32",
        "f64" => "f64",
        _ => "DeviceExtremes",
    }
}

fn c_element(e: &str) -> &'static str {
    match e {
        "f32" => "float",
        "u32" => "u32",
        "i32" => "int",
        "f64" => "double",
        _ => "Extremes",
    }
}

/// An argument's C++ type: in a kernel's signature (`kernel`: the structs by value, buffers
/// `__restrict__`), or in a shim launcher's (the structs by pointer).
fn c_type(ty: ArgType, kernel: bool) -> String {
    match ty {
        ArgType::Scalar("u32") => "u32".to_string(),
        ArgType::Scalar("i32") => "int".to_string(),
        ArgType::Scalar(_) => "float".to_string(),
        ArgType::Params if kernel => "StepParams".to_string(),
        ArgType::Params => "const StepParams*".to_string(),
        ArgType::Grid if kernel => "GridGeometry".to_string(),
        ArgType::Grid => "const GridGeometry*".to_string(),
        ArgType::Buffer { element, write } => format!(
            "{}{}*{}",
            if write { "" } else { "const " },
            c_element(element),
            if kernel { " __restrict__" } else { "" }
        ),
    }
}

/// The trait method's parameters after `&self` (and the family index).
fn method_params(e: &Entry, buf: &str, params: &str, grid: &str) -> String {
    e.args
        .iter()
        .map(|a| {
            let ty = match a.ty {
                ArgType::Scalar(s) => s.to_string(),
                ArgType::Params => format!("&{params}"),
                ArgType::Grid => format!("&{grid}"),
                ArgType::Buffer { element, write } => {
                    let inner = buf.replace("T", rust_element(element));
                    if write {
                        format!("&mut {inner}")
                    } else {
                        format!("&{inner}")
                    }
                }
            };
            format!("{}: {ty}", a.name)
        })
        .collect::<Vec<_>>()
        .join(", ")
}

fn doc(e: &Entry) -> String {
    let what = if e.kernels.len() == 1 {
        format!("`{}`", e.kernels[0])
    } else {
        format!(
            "the `{}` entry `entry` of [`{}`]",
            e.method,
            e.method.to_uppercase()
        )
    };
    format!(
        "    /// Launches {what} of `kernels/` over `{}` threads.\n    ///\n    /// # Safety\n    /// \
         Every buffer holds the items the kernel reads or writes.\n",
        e.threads
    )
}

/// `$OUT_DIR/launch.rs` (names, the `Launch` trait, its cudarc and shim implementations) and
/// `$OUT_DIR/shim_externs.rs` (the shim's launchers for 2D and 3D).
pub fn rust(entries: &[Entry]) -> (String, String) {
    let mut s = String::from("// Generated by build.rs from kernels/launch.table; do not edit.\n\n");
    let names: Vec<&String> = entries.iter().flat_map(|e| &e.kernels).collect();
    let _ = writeln!(
        s,
        "/// Every kernel entry of `kernels/launch.table`, in table order."
    );
    let _ = writeln!(s, "pub const KERNEL_NAMES: [&str; {}] = [", names.len());
    for n in &names {
        let _ = writeln!(s, "    {n:?},");
    }
    let _ = writeln!(s, "];\n");
    let mut index = 0usize;
    let mut base = Vec::new();
    for e in entries {
        base.push(index);
        if e.kernels.len() > 1 {
            let _ = writeln!(s, "/// The entries of the `{}` family, by index.", e.method);
            let _ = writeln!(
                s,
                "pub const {}: [&str; {}] = [",
                e.method.to_uppercase(),
                e.kernels.len()
            );
            for k in &e.kernels {
                let _ = writeln!(s, "    {k:?},");
            }
            let _ = writeln!(s, "];\n");
        }
        index += e.kernels.len();
    }

    // The trait.
    s.push_str(
        "/// One launch per line of `kernels/launch.table`, on the device `Self` (cudarc's GPU or \
         the host shim).\n#[allow(clippy::too_many_arguments, clippy::missing_safety_doc)]\n\
         pub trait Launch<const D: usize>: Memory {\n",
    );
    for e in entries {
        s.push_str(&doc(e));
        let family = if e.kernels.len() > 1 { "entry: usize, " } else { "" };
        let _ = writeln!(
            s,
            "    unsafe fn {}(&self, {family}{}) -> Result<(), DeviceFault>;",
            e.method,
            method_params(e, "Self::Buf<T>", "StepParams<D>", "GridGeometry<D>")
        );
    }
    s.push_str("}\n\n");

    // cudarc.
    s.push_str("#[allow(clippy::too_many_arguments)]\nimpl<const D: usize> Launch<D> for Gpu {\n");
    for (e, &b) in entries.iter().zip(&base) {
        let family = if e.kernels.len() > 1 { "entry: usize, " } else { "" };
        let _ = writeln!(
            s,
            "    unsafe fn {}(&self, {family}{}) -> Result<(), DeviceFault> {{",
            e.method,
            method_params(e, "CudaSlice<T>", "StepParams<D>", "GridGeometry<D>")
        );
        let idx = if e.kernels.len() > 1 {
            format!("{b} + entry")
        } else {
            format!("{b}")
        };
        let _ = writeln!(s, "        let mut builder = self.builder({idx});");
        for a in &e.args {
            match a.ty {
                ArgType::Scalar(_) => {
                    let _ = writeln!(s, "        builder.arg(&{});", a.name);
                }
                _ => {
                    let _ = writeln!(s, "        builder.arg({});", a.name);
                }
            }
        }
        let _ = writeln!(
            s,
            "        // SAFETY: the caller's (the buffers' sizes); the arguments are the kernel's, in order.\n        \
             unsafe {{ builder.launch(launch_config({})) }}.map(drop).map_err(DeviceFault::from)\n    }}",
            threads_rust(&e.threads)
        );
    }
    s.push_str("}\n\n");

    // Shim externs, per dimension.
    let mut externs = String::from("// Generated by build.rs from kernels/launch.table; do not edit.\n\n");
    for dim in [2, 3] {
        let _ = writeln!(
            externs,
            "#[link(name = \"sph_kernel_shim_{dim}\", kind = \"static\")]\nunsafe extern \"C\" {{"
        );
        for e in entries {
            for k in &e.kernels {
                let params: Vec<String> = e
                    .args
                    .iter()
                    .map(|a| {
                        let ty = match a.ty {
                            ArgType::Scalar(t) => t.to_string(),
                            ArgType::Params => format!("*const StepParams<{dim}>"),
                            ArgType::Grid => format!("*const GridGeometry<{dim}>"),
                            ArgType::Buffer { element, write } => format!(
                                "{} {}",
                                if write { "*mut" } else { "*const" },
                                rust_element(element)
                            ),
                        };
                        format!("{}: {ty}", a.name)
                    })
                    .collect();
                let _ = writeln!(
                    externs,
                    "    /// `{k}` of `kernels/` on the CPU, over `{}` threads.\n    pub fn sph_shim_{k}_{dim}({});",
                    e.threads,
                    params.join(", ")
                );
            }
        }
        externs.push_str("}\n\n");
    }
    // One implementation for every `D`: the kernels built for `D` (2 or 3), whose `StepParams`
    // and `GridGeometry` are the caller's, so code generic over `D` needs no `Shim: Launch<D>`.
    s.push_str("#[allow(clippy::too_many_arguments)]\nimpl<const D: usize> Launch<D> for Shim {\n");
    for e in entries {
        let family = e.kernels.len() > 1;
        let _ = writeln!(
            s,
            "    unsafe fn {}(&self, {}{}) -> Result<(), DeviceFault> {{",
            e.method,
            if family { "entry: usize, " } else { "" },
            method_params(e, "Vec<T>", "StepParams<D>", "GridGeometry<D>")
        );
        let call_args: Vec<String> = e
            .args
            .iter()
            .map(|a| match a.ty {
                ArgType::Scalar(_) => a.name.clone(),
                ArgType::Params | ArgType::Grid => format!("std::ptr::from_ref({}).cast()", a.name),
                ArgType::Buffer { write: true, .. } => format!("{}.as_mut_ptr()", a.name),
                ArgType::Buffer { write: false, .. } => format!("{}.as_ptr()", a.name),
            })
            .collect();
        let call_args = call_args.join(", ");
        s.push_str(
            "        // SAFETY: the caller's; the kernels of dimension `D` take `D`'s parameters.\n        unsafe {\n",
        );
        if family {
            s.push_str("            match (D, entry) {\n");
            for dim in [2, 3] {
                for (i, k) in e.kernels.iter().enumerate() {
                    let _ = writeln!(
                        s,
                        "                ({dim}, {i}) => super::shim::sph_shim_{k}_{dim}({call_args}),"
                    );
                }
            }
            let _ = writeln!(
                s,
                "                _ => return Err(DeviceFault(format!(\"no entry {{entry}} of `{}` in {{D}}D\"))),",
                e.method
            );
        } else {
            s.push_str("            match D {\n");
            for dim in [2, 3] {
                let _ = writeln!(
                    s,
                    "                {dim} => super::shim::sph_shim_{}_{dim}({call_args}),",
                    e.kernels[0]
                );
            }
            s.push_str(
                "                _ => return Err(DeviceFault(format!(\"the host shim has no {D}D kernels\"))),\n",
            );
        }
        s.push_str("            }\n        }\n        Ok(())\n    }\n");
    }
    s.push_str("}\n\n");
    (s, externs)
}

/// `$OUT_DIR/shim_exports.inc`: one C++ launcher per kernel entry, with the table's shape.
pub fn cpp(entries: &[Entry]) -> String {
    let mut s = String::from("// Generated by build.rs from kernels/launch.table; do not edit.\n");
    for e in entries {
        let params: Vec<String> = e
            .args
            .iter()
            .map(|a| {
                let ty = c_type(a.ty, false);
                // Suffixed: a parameter named as a kernel (`density`) would hide it.
                format!("{ty} {}_", a.name)
            })
            .collect();
        let pass: Vec<String> = e
            .args
            .iter()
            .map(|a| match a.ty {
                ArgType::Params | ArgType::Grid => format!("*{}_", a.name),
                _ => format!("{}_", a.name),
            })
            .collect();
        for k in &e.kernels {
            let _ = writeln!(
                s,
                "SPH_EXPORT({k})({}) {{\n    SPH_LAUNCH(SPH_BLOCKS({}), SPH_THREADS, {k}, {});\n}}",
                params.join(", "),
                threads_c(&e.threads),
                pass.join(", ")
            );
        }
    }
    s
}
