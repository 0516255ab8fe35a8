//! The report's text, written once as blocks and rendered twice: `report.md` (to paste into
//! a paper or a review) and `index.html` (self-contained but for the plots beside it).

use std::fmt::Write as _;

/// One block of the report.
pub enum Block {
    Heading(u8, String),
    Paragraph(String),
    /// A header row and the rows under it.
    Table(Vec<String>, Vec<Vec<String>>),
    /// An image file beside the report, and its description.
    Image(String, String),
}

/// The blocks as Markdown.
pub fn markdown(blocks: &[Block]) -> String {
    let mut out = String::new();
    for block in blocks {
        match block {
            Block::Heading(level, text) => {
                let _ = writeln!(out, "{} {text}\n", "#".repeat(usize::from(*level)));
            }
            Block::Paragraph(text) => {
                let _ = writeln!(out, "{text}\n");
            }
            Block::Table(header, rows) => {
                let line = |cells: &[String]| {
                    let cells: Vec<String> = cells.iter().map(|c| c.replace('|', "\\|")).collect();
                    format!("| {} |", cells.join(" | "))
                };
                let _ = writeln!(out, "{}", line(header));
                let _ = writeln!(out, "|{}", " --- |".repeat(header.len()));
                for row in rows {
                    let _ = writeln!(out, "{}", line(row));
                }
                out.push('\n');
            }
            Block::Image(file, alt) => {
                let _ = writeln!(out, "![{alt}]({file})\n");
            }
        }
    }
    out
}

/// The blocks as one HTML page, under `title`.
pub fn html(title: &str, blocks: &[Block]) -> String {
    let mut out = format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{}</title>\n\
         <style>\nbody {{ font-family: sans-serif; margin: 2em auto; max-width: 78em; color: #222; }}\n\
         table {{ border-collapse: collapse; margin: 1em 0; font-size: 0.9em; }}\n\
         th, td {{ border: 1px solid #bbb; padding: 0.25em 0.6em; text-align: right; }}\n\
         th {{ background: #eee; }}\ntd:first-child, td:nth-child(2) {{ text-align: left; }}\n\
         img {{ max-width: 100%; border: 1px solid #ddd; }}\n</style>\n</head>\n<body>\n",
        escape(title)
    );
    for block in blocks {
        match block {
            Block::Heading(level, text) => {
                let _ = writeln!(out, "<h{level}>{}</h{level}>", escape(text));
            }
            Block::Paragraph(text) => {
                let _ = writeln!(out, "<p>{}</p>", code_spans(&escape(text)));
            }
            Block::Table(header, rows) => {
                out.push_str("<table>\n<tr>");
                for cell in header {
                    let _ = write!(out, "<th>{}</th>", escape(cell));
                }
                out.push_str("</tr>\n");
                for row in rows {
                    out.push_str("<tr>");
                    for cell in row {
                        let _ = write!(out, "<td>{}</td>", escape(cell));
                    }
                    out.push_str("</tr>\n");
                }
                out.push_str("</table>\n");
            }
            Block::Image(file, alt) => {
                let _ = writeln!(
                    out,
                    "<p><img src=\"{}\" alt=\"{}\"></p>",
                    escape(file),
                    escape(alt)
                );
            }
        }
    }
    out.push_str("</body>\n</html>\n");
    out
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Markdown's `code` spans as HTML's.
fn code_spans(text: &str) -> String {
    let mut out = String::new();
    for (i, part) in text.split('`').enumerate() {
        if i % 2 == 1 {
            let _ = write!(out, "<code>{part}</code>");
        } else {
            out.push_str(part);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn blocks() -> Vec<Block> {
        vec![
            Block::Heading(1, "Report <city>".into()),
            Block::Paragraph("Run `shadowlab report`.".into()),
            Block::Table(
                vec!["method".into(), "ms".into()],
                vec![
                    vec!["vfc".into(), "1.50".into()],
                    vec!["a|b".into(), "2".into()],
                ],
            ),
            Block::Image("speed.png".into(), "speed against error".into()),
        ]
    }

    #[test]
    fn markdown_and_html_carry_the_same_blocks() {
        let md = markdown(&blocks());
        assert!(md.starts_with("# Report <city>\n"));
        assert!(md.contains("| method | ms |\n| --- | --- |\n| vfc | 1.50 |\n| a\\|b | 2 |\n"));
        assert!(md.contains("![speed against error](speed.png)"));
        let page = html("t", &blocks());
        assert!(page.contains("<h1>Report &lt;city&gt;</h1>"));
        assert!(page.contains("<p>Run <code>shadowlab report</code>.</p>"));
        assert!(page.contains("<tr><td>vfc</td><td>1.50</td></tr>"));
        assert!(page.contains("<img src=\"speed.png\" alt=\"speed against error\">"));
        assert!(page.ends_with("</html>\n"));
    }
}
