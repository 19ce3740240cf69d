//! `merge`: Mitsuba 3's pseudo-shape that merges its child meshes into one mesh per
//! BSDF they share (src/shapes/merge.cpp), a speed-up of Mitsuba's own. What it renders
//! is its shapes as they are, so each child `<shape>` (nested `merge`s too, and
//! shapes with emitters, sensors or media, which Mitsuba keeps apart) is loaded as if
//! it stood at the top level. As in Mitsuba 3.9.1, a merge takes no parameters (one is
//! an error) and other nested objects are ignored (a `<bsdf>` given to the merge itself
//! is not its shapes').
//!
//! ```xml
//! <shape type="merge">
//!     <shape type="obj"><string name="filename" value="a.obj"/></shape>
//!     <shape type="obj"><string name="filename" value="b.obj"/></shape>
//! </shape>
//! ```

use crate::scene::plugin::{Family, PluginDoc};
use crate::scene::xml::Dialect;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Shape,
    Dialect::Mitsuba,
    "merge",
    "Its nested shapes, each as if at the top level (Mitsuba merges meshes that share a BSDF into one, which renders the same); no parameters.",
    &[],
);

#[cfg(test)]
mod tests {
    use crate::scene::testutil::{error_at, load};

    const SHAPES: &str = "<shape type=\"rectangle\"><emitter type=\"area\"><rgb name=\"radiance\" value=\"2\"/></emitter></shape>\n<shape type=\"cube\"><bsdf type=\"conductor\"/><transform name=\"to_world\"><translate x=\"2\"/></transform></shape>\n<shape type=\"sphere\"><float name=\"radius\" value=\"0.5\"/></shape>\n";

    fn scene(body: &str) -> String {
        format!("<scene version=\"3.0.0\">\n<sensor type=\"perspective\"/>\n{body}</scene>\n")
    }

    #[test]
    fn children_load_as_top_level_shapes() {
        let plain = load(&[("s.xml", &scene(SHAPES))], &[]).unwrap();
        // The sphere in a nested merge; a BSDF of the merge itself is ignored.
        let (a, b) = SHAPES.split_at(SHAPES.find("<shape type=\"sphere\"").unwrap());
        let merged = scene(&format!(
            "<shape type=\"merge\" id=\"m\">\n<bsdf type=\"dielectric\"/>\n{a}<shape type=\"merge\">\n{b}</shape>\n</shape>\n"
        ));
        let merged = load(&[("s.xml", &merged)], &[]).unwrap();
        assert_eq!(merged.meshes.len(), 2);
        assert_eq!(merged.quadrics.len(), 1);
        for (m, p) in merged.meshes.iter().zip(&plain.meshes) {
            assert_eq!(
                (&m.positions, &m.indices, m.bsdf, m.emitter),
                (&p.positions, &p.indices, p.bsdf, p.emitter)
            );
        }
        assert_eq!(merged.quadrics[0].to_world, plain.quadrics[0].to_world);
        assert_eq!(merged.emitters.len(), plain.emitters.len());
        assert_eq!(merged.bsdfs.len(), plain.bsdfs.len());
        // An empty merge is no error, as in Mitsuba.
        load(&[("s.xml", &scene("<shape type=\"merge\"/>\n"))], &[]).unwrap();
    }

    #[test]
    fn parameters_are_refused() {
        let e = error_at(
            load(
                &[(
                    "s.xml",
                    &scene("<shape type=\"merge\">\n<float name=\"x\" value=\"1\"/>\n<shape type=\"sphere\"/>\n</shape>\n"),
                )],
                &[],
            ),
            "s.xml",
            4,
        );
        assert!(e.contains("'x'"), "{e}");
    }
}
