//! Reading PNML text (either dialect) into a [`PetriNet`].

use roxmltree::{Document, Node};

use super::Dialect;
use super::error::PnmlError;
use crate::net::{PetriNet, PlaceNode, Position, TransitionNode};

/// The prefix of a comment that names the plan (JARP dialect).
pub(super) const PLAN_NAME_PREFIX: &str = "PLAN NAME:";

/// Reads a net from PNML text, in the JARP or the standard dialect (detected).
///
/// Only the first `net` is read. Places, transitions, arcs and comments are taken
/// from the net itself and from its pages, nested or not, in document order.
/// Element names are matched on their local name, so namespaces do not matter.
/// A label is the text of `name/value` (JARP) or `name/text` (standard), kept
/// verbatim; a missing name gives an empty label. An initial marking or an arc
/// inscription counts what follows its last comma (`Default,1` reads 1); when
/// absent, the marking is 0 and the weight 1. Of the graphics, only a node's
/// `graphics/position` is kept; tool-specific data is ignored.
///
/// The plan's name is the (trimmed) rest of the last comment whose text starts
/// with `PLAN NAME:` (case-sensitive, as in the reference library; leading
/// white space is skipped); failing that, in the standard dialect, the trimmed
/// text of `net/name` (JARP's `net/name` is the editor's `P/T net` and is
/// ignored); failing that, `fallback_name`. The dialect is standard when the
/// document uses the PNML namespace or net type or has a `page`.
///
/// Node ids must be present and non-empty; an initial marking or inscription
/// must be an integer from 0 to 255 (weight 0 is then rejected by the net);
/// everything [`PetriNet::new`] checks is checked. Never panics.
pub fn parse(text: &str, fallback_name: &str) -> Result<PetriNet, PnmlError> {
    let doc = Document::parse(text).map_err(|e| {
        let message = e.to_string();
        let pos = match e {
            // roxmltree reports these at 1:1; the fault is where the text ends.
            roxmltree::Error::UnexpectedEndOfStream | roxmltree::Error::UnclosedRootNode => end_of(text),
            _ => e.pos(),
        };
        // The position is in the variant's own fields; drop roxmltree's copy.
        let suffix = format!(" at {}", e.pos());
        PnmlError::Xml {
            line: pos.row,
            column: pos.col,
            message: message.strip_suffix(&suffix).unwrap_or(&message).to_string(),
        }
    })?;
    check_nesting(&doc)?;
    let root = doc.root_element();
    if !is(root, "pnml") {
        return Err(PnmlError::NotPnml {
            found: root.tag_name().name().to_string(),
        });
    }
    let net = child(root, "net").ok_or(PnmlError::NoNet)?;

    let mut places = Vec::new();
    let mut transitions = Vec::new();
    let mut arcs: Vec<(String, String, String, u8)> = Vec::new();
    let mut plan_name = None;
    // Depth-first over the net and its pages, without recursion: a hostile file
    // may nest pages deeper than the stack allows.
    let mut stack = vec![net.children()];
    while let Some(children) = stack.last_mut() {
        let Some(node) = children.next() else {
            stack.pop();
            continue;
        };
        if !node.is_element() {
            continue;
        }
        match node.tag_name().name() {
            "page" => stack.push(node.children()),
            "place" => {
                let id = id_of(&doc, node, "place")?;
                let initial = count(node, "initialMarking", 0).map_err(|text| PnmlError::BadCount {
                    element: "place",
                    id: id.clone(),
                    field: "initial marking",
                    text,
                })?;
                places.push(PlaceNode {
                    label: label(node),
                    initial,
                    position: position(node),
                    id,
                });
            }
            "transition" => transitions.push(TransitionNode {
                id: id_of(&doc, node, "transition")?,
                label: label(node),
                position: position(node),
            }),
            "arc" => {
                let id = id_of(&doc, node, "arc")?;
                let end = |end: &'static str| {
                    node.attribute(end)
                        .map(str::to_string)
                        .ok_or_else(|| PnmlError::MissingEnd { arc: id.clone(), end })
                };
                let source = end("source")?;
                let target = end("target")?;
                let weight = count(node, "inscription", 1).map_err(|text| PnmlError::BadCount {
                    element: "arc",
                    id: id.clone(),
                    field: "inscription",
                    text,
                })?;
                arcs.push((id, source, target, weight));
            }
            "comment" => {
                if let Some(name) = comment_plan_name(node) {
                    plan_name = Some(name);
                }
            }
            _ => {}
        }
    }

    let name = plan_name
        .or_else(|| match detect(root, net) {
            Dialect::Standard => child(net, "name").and_then(value_of).map(trimmed),
            Dialect::Jarp => None,
        })
        .unwrap_or_else(|| fallback_name.to_string());
    let specs: Vec<_> = arcs
        .iter()
        .map(|(id, source, target, weight)| (id.as_str(), source.as_str(), target.as_str(), *weight))
        .collect();
    Ok(PetriNet::new(name, places, transitions, &specs)?)
}

/// The deepest element nesting a plan file may have. PNML needs a handful of
/// levels (`pnml/net/page/place/name/text`, pages nested a few times); a
/// deeper document is refused rather than read, whatever it holds.
pub const MAX_NESTING: usize = 100;

/// Refuses a document whose elements nest deeper than [`MAX_NESTING`],
/// naming the first element beyond it.
fn check_nesting(doc: &Document) -> Result<(), PnmlError> {
    // Node ids follow document order, so a parent's depth is known before its children's.
    let mut depth: Vec<u32> = Vec::new();
    for node in doc.root().descendants() {
        let d = node
            .parent()
            .and_then(|p| depth.get(p.id().get_usize()))
            .map_or(0, |&d| d + u32::from(node.is_element()));
        if d as usize > MAX_NESTING {
            let pos = doc.text_pos_at(node.range().start);
            return Err(PnmlError::TooDeep {
                line: pos.row,
                column: pos.col,
                limit: MAX_NESTING,
            });
        }
        depth.push(d);
    }
    Ok(())
}

/// The position just past the end of `text`.
fn end_of(text: &str) -> roxmltree::TextPos {
    let line = text.matches('\n').count() + 1;
    let last = text.rsplit('\n').next().unwrap_or("");
    roxmltree::TextPos::new(
        u32::try_from(line).unwrap_or(u32::MAX),
        u32::try_from(last.chars().count() + 1).unwrap_or(u32::MAX),
    )
}

/// The dialect of a document: standard if it uses the PNML namespace or net
/// type, or puts anything in a page; JARP otherwise.
fn detect(root: Node, net: Node) -> Dialect {
    const PNML_ORG: &str = "http://www.pnml.org/";
    let standard = root.tag_name().namespace().is_some_and(|ns| ns.starts_with(PNML_ORG))
        || net.attribute("type").is_some_and(|t| t.trim().starts_with(PNML_ORG))
        || child(net, "page").is_some();
    if standard { Dialect::Standard } else { Dialect::Jarp }
}

/// Whether `node` is an element with this local name.
fn is(node: Node, name: &str) -> bool {
    node.is_element() && node.tag_name().name() == name
}

/// The first child element with this local name.
fn child<'a, 'input>(node: Node<'a, 'input>, name: &str) -> Option<Node<'a, 'input>> {
    node.children().find(|c| is(*c, name))
}

/// The text directly inside an element (all its text children, joined).
fn own_text(node: Node) -> String {
    node.children().filter_map(|c| c.text()).collect()
}

/// The text of the first `value` (JARP) or `text` (standard) child, if any.
fn value_of(node: Node) -> Option<String> {
    node.children()
        .find(|c| is(*c, "value") || is(*c, "text"))
        .map(own_text)
}

fn trimmed(s: String) -> String {
    s.trim().to_string()
}

/// A node's id, which must be present and non-empty.
fn id_of(doc: &Document, node: Node, element: &'static str) -> Result<String, PnmlError> {
    match node.attribute("id") {
        Some(id) if !id.is_empty() => Ok(id.to_string()),
        _ => {
            let pos = doc.text_pos_at(node.range().start);
            Err(PnmlError::MissingId {
                element,
                line: pos.row,
                column: pos.col,
            })
        }
    }
}

/// A node's label: the value of its `name`, or empty.
fn label(node: Node) -> String {
    child(node, "name").and_then(value_of).unwrap_or_default()
}

/// The count in the `field` child of `node` (the part after its last comma), or
/// `default` when the field or its value is absent; the trimmed text when bad.
fn count(node: Node, field: &str, default: u8) -> Result<u8, String> {
    let Some(text) = child(node, field).and_then(value_of) else {
        return Ok(default);
    };
    let tail = text.rsplit_once(',').map_or(text.as_str(), |(_, tail)| tail);
    tail.trim().parse().map_err(|_| text.trim().to_string())
}

/// `graphics/position` of a node, when both coordinates are finite numbers.
fn position(node: Node) -> Option<Position> {
    let pos = child(child(node, "graphics")?, "position")?;
    let coord = |name: &str| {
        pos.attribute(name)?
            .trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
    };
    Some(Position {
        x: coord("x")?,
        y: coord("y")?,
    })
}

/// The plan name a comment gives, if one of its texts starts with `PLAN NAME:`.
fn comment_plan_name(comment: Node) -> Option<String> {
    comment
        .children()
        .filter(|c| is(*c, "text"))
        .filter_map(|t| {
            let text = value_of(t).unwrap_or_else(|| own_text(t));
            text.trim_start()
                .strip_prefix(PLAN_NAME_PREFIX)
                .map(|rest| rest.trim().to_string())
        })
        .next_back()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn count_takes_the_part_after_the_last_comma() {
        let doc = Document::parse(
            "<p><m><value>Default,3</value></m><n><text> 7 </text></n><o><value>a,b,2</value></o>\
             <q><value>x</value></q><r/></p>",
        )
        .unwrap();
        let p = doc.root_element();
        assert_eq!(count(p, "m", 0), Ok(3));
        assert_eq!(count(p, "n", 0), Ok(7));
        assert_eq!(count(p, "o", 0), Ok(2));
        assert_eq!(count(p, "q", 0), Err("x".to_string()));
        assert_eq!(count(p, "r", 1), Ok(1));
        assert_eq!(count(p, "missing", 1), Ok(1));
    }

    #[test]
    fn detects_dialects() {
        let dialect = |text: &str| {
            let doc = Document::parse(text).unwrap();
            let root = doc.root_element();
            detect(root, child(root, "net").unwrap())
        };
        assert_eq!(dialect("<pnml><net type='PTNet'/></pnml>"), Dialect::Jarp);
        assert_eq!(dialect("<pnml><net><page id='g'/></net></pnml>"), Dialect::Standard);
        assert_eq!(
            dialect("<pnml xmlns='http://www.pnml.org/version-2009/grammar/pnml'><net/></pnml>"),
            Dialect::Standard
        );
        assert_eq!(
            dialect("<pnml><net type='http://www.pnml.org/version-2009/grammar/pnmlcoremodel'/></pnml>"),
            Dialect::Standard
        );
    }
}
