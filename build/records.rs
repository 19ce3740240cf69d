//! The GLSL side of the GPU records declared in `src/gpu/records.rs`, written by
//! build.rs to `$OUT_DIR/glsl/generated/records.glsl` (included by
//! `shaders/scene/layout.glsl`; glslang finds it through `-I$OUT_DIR/glsl`).
//!
//! For each record: its struct, laid out by std430 (this generator checks every
//! offset and size against Rust's and fails the build if one differs). For each record
//! that is whole 16-byte texels, as the kernels read them (uvec4 image loads):
//!
//! - `T_TEXELS`: its texels;
//! - `T_WORDk(R)`: texel k of record `R`, a uvec4 expression;
//! - `T_LOAD(fn, texel)`: defines `T fn(uint i)`, record i of an array whose texel k
//!   `texel(k)` returns;
//! - `T_STORE(fn, store)`: defines `void fn(uint i, T R)`, which calls `store(k, w)`
//!   with each texel of record i;
//!
//! and `RECORDS(X)` expands `X(T)` for each of them.

use crate::records::{Field, Record, RECORDS};
use std::fmt::Write;
use std::path::Path;

/// Writes `records.glsl` under `glsl_dir` (`glsl_dir/generated/records.glsl`).
pub fn write(glsl_dir: &Path) {
    println!("cargo:rerun-if-changed=src/gpu/records.rs");
    println!("cargo:rerun-if-changed=build/records.rs");
    let dir = glsl_dir.join("generated");
    std::fs::create_dir_all(&dir).expect("create $OUT_DIR/glsl/generated");
    std::fs::write(dir.join("records.glsl"), glsl(RECORDS)).expect("write records.glsl");
}

/// A GLSL type: its scalar kind (`f`, `u`, `i`), columns, rows (components per
/// column), and std430 size and alignment.
struct Ty {
    kind: char,
    columns: usize,
    rows: usize,
    size: usize,
    align: usize,
}

fn ty(glsl: &str) -> Ty {
    let (kind, rest) = match glsl {
        "float" => ('f', "1"),
        "uint" => ('u', "1"),
        "int" => ('i', "1"),
        "mat4" => {
            return Ty {
                kind: 'f',
                columns: 4,
                rows: 4,
                size: 64,
                align: 16,
            }
        }
        _ if glsl.starts_with("vec") => ('f', &glsl[3..]),
        _ if glsl.starts_with("uvec") => ('u', &glsl[4..]),
        _ if glsl.starts_with("ivec") => ('i', &glsl[4..]),
        _ => panic!("records.rs: GLSL type {glsl} is not one build/records.rs knows"),
    };
    let rows: usize = rest.parse().expect("vector size");
    Ty {
        kind,
        columns: 1,
        rows,
        size: 4 * rows,
        align: if rows == 3 { 16 } else { 4 * rows },
    }
}

/// Array stride (std430) of `t`.
fn stride(t: &Ty) -> usize {
    t.size.next_multiple_of(t.align)
}

/// Comment lines (`// `) of a doc string, indented by `indent`.
fn comment(out: &mut String, doc: &str, indent: &str) {
    for line in doc.lines() {
        let line = line.strip_prefix(' ').unwrap_or(line).trim_end();
        if line.is_empty() {
            writeln!(out, "{indent}//").unwrap();
        } else {
            writeln!(out, "{indent}// {line}").unwrap();
        }
    }
}

/// The std430 struct of `r`, after checking its layout against Rust's.
fn glsl_struct(out: &mut String, r: &Record) {
    let mut offset = 0usize;
    let mut align_max = 4usize;
    comment(out, r.doc, "");
    writeln!(out, "struct {} {{", r.name).unwrap();
    for f in r.fields {
        let t = ty(f.glsl);
        offset = offset.next_multiple_of(t.align);
        let size = if f.len == 0 {
            t.size
        } else {
            stride(&t) * f.len
        };
        assert_eq!(
            (offset, size),
            (f.offset, f.size),
            "records.rs: {}.{} is at {} ({} bytes) in Rust, at {offset} ({size} bytes) as \
             GLSL {} under std430",
            r.name,
            f.name,
            f.offset,
            f.size,
            f.glsl
        );
        offset += size;
        align_max = align_max.max(t.align);
        comment(out, f.doc, "    ");
        let array = if f.len == 0 {
            String::new()
        } else {
            format!("[{}]", f.len)
        };
        writeln!(out, "    {} {}{array};", f.glsl, f.name).unwrap();
    }
    assert_eq!(
        offset.next_multiple_of(align_max),
        r.size,
        "records.rs: {} is {} bytes in Rust, {} under std430",
        r.name,
        r.size,
        offset.next_multiple_of(align_max)
    );
    out.push_str("};\n\n");
}

/// One vector of a field: a column of an element (`access` is the GLSL expression
/// after the record, e.g. `.table[3]`, `.world_to_grid[1]`), at byte `offset`.
struct Piece {
    access: String,
    offset: usize,
    rows: usize,
    kind: char,
}

fn pieces(f: &Field) -> Vec<Piece> {
    let t = ty(f.glsl);
    let mut out = Vec::new();
    for e in 0..f.len.max(1) {
        let element = if f.len == 0 {
            format!(".{}", f.name)
        } else {
            format!(".{}[{e}]", f.name)
        };
        for c in 0..t.columns {
            out.push(Piece {
                access: if t.columns == 1 {
                    element.clone()
                } else {
                    format!("{element}[{c}]")
                },
                offset: f.offset + e * stride(&t) + c * 16,
                rows: t.rows,
                kind: t.kind,
            });
        }
    }
    out
}

/// `w3.xyz`: the words of `p` in the texels `w0`, `w1`, ... of a record.
fn words(p: &Piece) -> String {
    let (texel, first) = (p.offset / 16, p.offset % 16 / 4);
    assert!(first + p.rows <= 4, "a vector crosses a texel");
    if p.rows == 4 {
        format!("w{texel}")
    } else {
        format!("w{texel}.{}", &"xyzw"[first..first + p.rows])
    }
}

/// The GLSL value of `p` loaded from its texels.
fn load(p: &Piece) -> String {
    let w = words(p);
    match (p.kind, p.rows) {
        ('f', _) => format!("uintBitsToFloat({w})"),
        ('u', _) => w,
        ('i', 1) => format!("int({w})"),
        ('i', n) => format!("ivec{n}({w})"),
        _ => unreachable!(),
    }
}

/// The value of field `f` of a record loaded from its texels.
fn load_field(f: &Field) -> String {
    let t = ty(f.glsl);
    let ps = pieces(f);
    let per_element: Vec<String> = ps
        .chunks(t.columns)
        .map(|cols| {
            if t.columns == 1 {
                load(&cols[0])
            } else {
                let c: Vec<_> = cols.iter().map(load).collect();
                format!("{}({})", f.glsl, c.join(", "))
            }
        })
        .collect();
    if f.len == 0 {
        per_element.into_iter().next().expect("one element")
    } else {
        format!("{}[{}]({})", f.glsl, f.len, per_element.join(", "))
    }
}

/// The uvec4 of texel `k` of record `R` (words of no field: 0).
fn store_texel(r: &Record, k: usize) -> String {
    let mut parts = Vec::new();
    let mut word = 4 * k;
    for p in r.fields.iter().flat_map(pieces) {
        let (first, end) = (p.offset / 4, p.offset / 4 + p.rows);
        if end <= 4 * k || first >= 4 * k + 4 {
            continue;
        }
        while word < first {
            parts.push("0u".to_string());
            word += 1;
        }
        let v = format!("R{}", p.access);
        parts.push(match (p.kind, p.rows) {
            ('f', _) => format!("floatBitsToUint({v})"),
            ('u', _) => v,
            ('i', 1) => format!("uint({v})"),
            ('i', n) => format!("uvec{n}({v})"),
            _ => unreachable!(),
        });
        word = end;
    }
    while word < 4 * k + 4 {
        parts.push("0u".to_string());
        word += 1;
    }
    format!("uvec4({})", parts.join(", "))
}

/// `T_TEXELS`, `T_WORDk`, `T_LOAD` and `T_STORE` of `r`, and `T_LOAD_SPLIT` and
/// `T_STORE_SPLIT`, which keep texel k of record i at k * stride + i.
fn glsl_access(out: &mut String, r: &Record) {
    let (n, t) = (r.size / 16, r.name);
    writeln!(out, "#define {t}_TEXELS {n}u").unwrap();
    for k in 0..n {
        writeln!(out, "#define {t}_WORD{k}(R) {}", store_texel(r, k)).unwrap();
    }
    writeln!(out, "#define {t}_LOAD(fn, texel) \\").unwrap();
    writeln!(out, "    {t} fn(uint i) {{ \\").unwrap();
    writeln!(out, "        uint b = {n}u * i; \\").unwrap();
    for k in 0..n {
        let at = if k == 0 {
            "b".to_string()
        } else {
            format!("b + {k}u")
        };
        writeln!(out, "        uvec4 w{k} = texel({at}); \\").unwrap();
    }
    let fields: Vec<String> = r.fields.iter().map(load_field).collect();
    writeln!(out, "        return {t}({}); \\", fields.join(", ")).unwrap();
    out.push_str("    }\n");
    // Texel k of record i at texel k * stride + i (a record split across arrays).
    writeln!(out, "#define {t}_LOAD_SPLIT(fn, texel, stride) \\").unwrap();
    writeln!(out, "    {t} fn(uint i) {{ \\").unwrap();
    for k in 0..n {
        writeln!(out, "        uvec4 w{k} = texel({k}u * (stride) + i); \\").unwrap();
    }
    writeln!(out, "        return {t}({}); \\", fields.join(", ")).unwrap();
    out.push_str("    }\n");
    writeln!(out, "#define {t}_STORE(fn, store) \\").unwrap();
    writeln!(out, "    void fn(uint i, {t} R) {{ \\").unwrap();
    writeln!(out, "        uint b = {n}u * i; \\").unwrap();
    for k in 0..n {
        let at = if k == 0 {
            "b".to_string()
        } else {
            format!("b + {k}u")
        };
        writeln!(out, "        store({at}, {t}_WORD{k}(R)); \\").unwrap();
    }
    out.push_str("    }\n");
    writeln!(out, "#define {t}_STORE_SPLIT(fn, store, stride) \\").unwrap();
    writeln!(out, "    void fn(uint i, {t} R) {{ \\").unwrap();
    for k in 0..n {
        writeln!(
            out,
            "        store({k}u * (stride) + i, {t}_WORD{k}(R)); \\"
        )
        .unwrap();
    }
    out.push_str("    }\n\n");
}

/// The whole of records.glsl.
pub fn glsl(records: &[Record]) -> String {
    let mut out = String::from(
        "// Generated by build.rs (build/records.rs) from src/gpu/records.rs: edit that.\n\
         #ifndef RECORDS_GLSL\n#define RECORDS_GLSL\n\n",
    );
    for r in records {
        glsl_struct(&mut out, r);
    }
    let texel_records: Vec<&Record> = records.iter().filter(|r| r.size % 16 == 0).collect();
    out.push_str(
        "// Loading and storing a record a texel at a time (build/records.rs says how).\n\n",
    );
    for r in &texel_records {
        glsl_access(&mut out, r);
    }
    let names: Vec<String> = texel_records
        .iter()
        .map(|r| format!("X({})", r.name))
        .collect();
    writeln!(out, "// X(T) for every record T above.").unwrap();
    writeln!(out, "#define RECORDS(X) {}\n", names.join(" ")).unwrap();
    out.push_str("#endif\n");
    out
}
