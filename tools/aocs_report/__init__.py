"""Reports: one document model (document.py: sections, paragraphs, tables with units, figures,
code) and its renderers, Markdown (markdown.py, the committed reports) and a self-contained HTML
page (html.py). The results, compare and campaign reports are built through it."""
