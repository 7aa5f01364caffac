//! The Markdown + SVG report of a diagnosis (placeholder, filled next).
