//! Writing a [`PetriNet`] as PNML text, in either dialect.

use std::collections::HashSet;

use xmlwriter::{Indent, Options, XmlWriter};

use super::Dialect;
use super::read::PLAN_NAME_PREFIX;
use crate::net::{ArcNode, PetriNet, Position};

/// The namespace of the 2009 PNML grammar.
const PNML_NAMESPACE: &str = "http://www.pnml.org/version-2009/grammar/pnml";
/// The net type of place/transition nets in the 2009 grammar.
const PTNET_TYPE: &str = "http://www.pnml.org/version-2009/grammar/ptnet";

/// The net as PNML text (UTF-8, with an XML declaration).
///
/// [`Dialect::Jarp`] writes what the JARP editor writes: a `PTNet` net whose
/// nodes sit directly in it, `<name><value>` labels, `Default,N` initial markings
/// and inscriptions, graphics for nodes with a position, label and inscription
/// offsets, JARP's `toolspecific` drawing settings, and a comment
/// `PLAN NAME: <name>` (the name also goes in `net/name`).
/// [`Dialect::Standard`] writes the 2009 place/transition grammar: namespace,
/// `ptnet` type, one page, `<text>` values, no initial marking when it is 0 and
/// no inscription when the weight is 1.
///
/// [`parse`](super::parse) reads the result back to an equal net, provided the
/// name has no leading or trailing white space, ids are not empty and positions
/// are finite (non-finite positions are not written). Characters that XML 1.0
/// cannot carry at all (control characters other than tab, line feed and
/// carriage return) are written as U+FFFD.
pub fn write(net: &PetriNet, dialect: Dialect) -> String {
    let mut w = XmlWriter::new(Options {
        indent: Indent::Spaces(2),
        ..Options::default()
    });
    w.write_declaration();
    let mut ids = FreshIds::new(net);
    match dialect {
        Dialect::Jarp => write_jarp(&mut w, net, &mut ids),
        Dialect::Standard => write_standard(&mut w, net, &mut ids),
    }
    w.end_document()
}

fn write_jarp(w: &mut XmlWriter, net: &PetriNet, ids: &mut FreshIds) {
    w.start_element("pnml");
    w.write_comment("generator: learnpnp");
    w.start_element("net");
    attribute(w, "id", &ids.fresh("n1"));
    attribute(w, "type", "PTNet");
    named(w, "name", "value", net.name());
    for place in net.places() {
        w.start_element("place");
        attribute(w, "id", &place.id);
        jarp_graphics(w, place.position, (32, 32));
        jarp_label(w, &place.label, (0, 40));
        named(w, "initialMarking", "value", &format!("Default,{}", place.initial));
        jarp_tool(w, Some(PLACE_FILL));
        w.end_element();
    }
    for transition in net.transitions() {
        w.start_element("transition");
        attribute(w, "id", &transition.id);
        jarp_graphics(w, transition.position, (48, 8));
        jarp_label(w, &transition.label, (0, -20));
        jarp_tool(w, Some(TRANSITION_FILL));
        w.end_element();
    }
    for arc in net.arcs() {
        start_arc(w, net, arc);
        w.start_element("inscription");
        text_element(w, "value", &format!("Default,{}", arc.weight));
        jarp_offset(w, (0, 0));
        w.end_element();
        jarp_tool(w, None);
        w.end_element();
    }
    w.start_element("comment");
    attribute(w, "id", &ids.fresh("c1"));
    named(w, "text", "value", &format!("{PLAN_NAME_PREFIX} {}", net.name()));
    w.end_element();
    w.end_element();
    w.end_element();
}

fn write_standard(w: &mut XmlWriter, net: &PetriNet, ids: &mut FreshIds) {
    w.start_element("pnml");
    w.write_attribute("xmlns", PNML_NAMESPACE);
    w.start_element("net");
    attribute(w, "id", &ids.fresh("net1"));
    attribute(w, "type", PTNET_TYPE);
    named(w, "name", "text", net.name());
    w.start_element("page");
    attribute(w, "id", &ids.fresh("page1"));
    for place in net.places() {
        w.start_element("place");
        attribute(w, "id", &place.id);
        named(w, "name", "text", &place.label);
        standard_graphics(w, place.position);
        if place.initial != 0 {
            named(w, "initialMarking", "text", &place.initial.to_string());
        }
        w.end_element();
    }
    for transition in net.transitions() {
        w.start_element("transition");
        attribute(w, "id", &transition.id);
        named(w, "name", "text", &transition.label);
        standard_graphics(w, transition.position);
        w.end_element();
    }
    for arc in net.arcs() {
        start_arc(w, net, arc);
        if arc.weight != 1 {
            named(w, "inscription", "text", &arc.weight.to_string());
        }
        w.end_element();
    }
    w.end_element();
    w.end_element();
    w.end_element();
}

/// JARP's fill colour of places (white).
const PLACE_FILL: &str = "java.awt.Color[r=255,g=255,b=255]";
/// JARP's fill colour of transitions (grey-blue, as PNPgen draws them).
const TRANSITION_FILL: &str = "java.awt.Color[r=200,g=200,b=220]";

/// A node's label as JARP writes it: its value and where it is drawn,
/// `offset` from the node.
fn jarp_label(w: &mut XmlWriter, label: &str, offset: (i32, i32)) {
    w.start_element("name");
    text_element(w, "value", label);
    jarp_offset(w, offset);
    w.end_element();
}

/// `<graphics><offset x= y=/></graphics>`: where JARP draws a label or an
/// inscription, relative to its node or arc.
fn jarp_offset(w: &mut XmlWriter, (x, y): (i32, i32)) {
    w.start_element("graphics");
    w.start_element("offset");
    w.write_attribute("x", &x);
    w.write_attribute("y", &y);
    w.end_element();
    w.end_element();
}

/// JARP's own drawing settings (`toolspecific tool="JARP"`): a node's frame
/// and `fill` colours, or an arc's colour and arrow (no `fill`).
fn jarp_tool(w: &mut XmlWriter, fill: Option<&str>) {
    w.start_element("toolspecific");
    w.write_attribute("tool", "JARP");
    w.write_attribute("version", "1.2");
    let frame = if fill.is_some() {
        "java.awt.Color[r=0,g=0,b=0]"
    } else {
        "java.awt.Color[r=128,g=128,b=128]"
    };
    named(w, "FrameColor", "value", frame);
    match fill {
        Some(fill) => named(w, "FillColor", "value", fill),
        None => named(w, "ArrowMode", "value", "2"),
    }
    w.end_element();
}

/// JARP's node graphics: position and size (JARP's default sizes).
fn jarp_graphics(w: &mut XmlWriter, position: Option<Position>, (width, height): (u32, u32)) {
    let Some(position) = position.filter(is_finite) else {
        return;
    };
    w.start_element("graphics");
    position_element(w, position);
    w.start_element("size");
    w.write_attribute("width", &width);
    w.write_attribute("height", &height);
    w.end_element();
    w.end_element();
}

/// The standard's node graphics: the position only.
fn standard_graphics(w: &mut XmlWriter, position: Option<Position>) {
    let Some(position) = position.filter(is_finite) else {
        return;
    };
    w.start_element("graphics");
    position_element(w, position);
    w.end_element();
}

fn is_finite(p: &Position) -> bool {
    p.x.is_finite() && p.y.is_finite()
}

/// `<position x= y=/>`; `f64`'s Display is the shortest text that reads back exactly.
fn position_element(w: &mut XmlWriter, position: Position) {
    w.start_element("position");
    w.write_attribute("x", &position.x);
    w.write_attribute("y", &position.y);
    w.end_element();
}

/// `<outer><inner>text</inner></outer>`, the text written verbatim (no indentation).
fn named(w: &mut XmlWriter, outer: &str, inner: &str, text: &str) {
    w.start_element(outer);
    text_element(w, inner, text);
    w.end_element();
}

/// `<element>text</element>`, the text written verbatim (no indentation).
fn text_element(w: &mut XmlWriter, element: &str, text: &str) {
    w.start_element(element);
    w.set_preserve_whitespaces(true);
    w.write_text(&escape(text, false));
    w.end_element();
    w.set_preserve_whitespaces(false);
}

/// An attribute with its value fully escaped.
/// Opens `arc`'s element with its id and its two ends, as both dialects write it.
fn start_arc(w: &mut XmlWriter, net: &PetriNet, arc: &ArcNode) {
    w.start_element("arc");
    attribute(w, "id", &arc.id);
    attribute(w, "source", net.node_id(arc.source));
    attribute(w, "target", net.node_id(arc.target));
}

fn attribute(w: &mut XmlWriter, name: &str, value: &str) {
    w.write_attribute(name, &escape(value, true));
}

/// XML-escapes `s` for text content or (with `attribute`) a quoted attribute value.
///
/// `xmlwriter` escapes only `<` in text and the quote in attributes, so every
/// markup character is escaped here. Carriage returns (and, in attributes, tabs
/// and line feeds) become character references so that XML's end-of-line and
/// attribute normalisation leave them intact; characters XML cannot carry
/// become U+FFFD.
fn escape(s: &str, attribute: bool) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '\r' => out.push_str("&#13;"),
            '"' if attribute => out.push_str("&quot;"),
            '\t' if attribute => out.push_str("&#9;"),
            '\n' if attribute => out.push_str("&#10;"),
            '\t' | '\n' => out.push(c),
            c if c < ' ' || c == '\u{FFFE}' || c == '\u{FFFF}' => out.push('\u{FFFD}'),
            c => out.push(c),
        }
    }
    out
}

/// Ids for the net, page and comment elements that no node or arc already uses.
struct FreshIds {
    taken: HashSet<String>,
}

impl FreshIds {
    fn new(net: &PetriNet) -> Self {
        let taken = net
            .places()
            .iter()
            .map(|p| p.id.clone())
            .chain(net.transitions().iter().map(|t| t.id.clone()))
            .chain(net.arcs().iter().map(|a| a.id.clone()))
            .collect();
        FreshIds { taken }
    }

    /// `base`, or `base_2`, `base_3`, ... whichever is free first; then taken.
    fn fresh(&mut self, base: &str) -> String {
        let id = std::iter::once(base.to_string())
            .chain((2u64..).map(|n| format!("{base}_{n}")))
            .find(|id| !self.taken.contains(id))
            .unwrap_or_else(|| base.to_string());
        self.taken.insert(id.clone());
        id
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_markup_and_line_ends() {
        assert_eq!(escape("a<b>&\"'\r\n\t", false), "a&lt;b&gt;&amp;\"'&#13;\n\t");
        assert_eq!(escape("a<b>&\"'\r\n\t", true), "a&lt;b&gt;&amp;&quot;'&#13;&#10;&#9;");
        assert_eq!(escape("x\u{1}y\u{FFFF}", false), "x\u{FFFD}y\u{FFFD}");
    }
}
