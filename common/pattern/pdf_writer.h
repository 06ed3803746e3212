#pragma once
// The pattern sheet as vector PDF at true scale (cairo's PDF surface), cut
// into pages for a home printer (A4, Letter), a copy shop's plotter (A0) or
// a roll plotter (914 mm roll), to print at 100 %:
//
// - page 1, the cover: the garment's name, "print at 100 %", a 10 cm x 10 cm
//   test square (and a 4 in one on Letter, whose users measure in inches) and
//   the page map: the sheet with every page's window, its label, and the
//   windows left out because no piece reaches them;
// - then one page per window that shows part of a piece, in rows A, B, ...
//   from the top and columns 1, 2, ... from the left. Windows overlap by
//   `overlap` (1 cm): the band along a page's right and bottom edges is
//   printed again along the next page's left and top edges. Each page has
//   its label ("B2") and its neighbours' at the edges, trim lines along its
//   left and top edges (cut there, then lay the page over its neighbour),
//   and alignment marks (a circle with a cross) in the middle of every
//   overlap band, which fall on each other when two pages are laid right.
//
// Pieces as on the SVG: cutting line solid, sewing line dashed, notches,
// grain line with arrows, darts (fold line, drill hole), the piece's label
// (name and what to cut, cut_instructions.h).
#include <ostream>
#include <string>
#include <vector>

#include "pattern/cut_instructions.h"
#include "pattern/layout.h"
#include "pattern/pattern.h"

namespace gp {

struct PaperSize {
  std::string name;       // "a4", "letter", "a0", "roll914"
  double width = 0.210;   // metres, portrait
  double height = 0.297;  // metres; a roll: the longest page the plotter takes
  bool inches = false;    // a second test square of 4 in (Letter)
  bool roll = false;      // pages end where the content does along the roll
};

// The four papers export-rest prints on. A0: ISO 216, 841 x 1189 mm. The
// roll: 914 mm (36 in) wide, pages up to 2.5 m long.
PaperSize paper_a4();
PaperSize paper_letter();
PaperSize paper_a0();
PaperSize paper_roll914();

// The papers export-rest writes a PDF for, in order: A4, Letter, A0, roll.
std::vector<PaperSize> pdf_papers();

struct PdfOptions {
  PaperSize paper;
  double margin = 0.01;        // metres: unprinted edge of the paper (home printers leave 3-6 mm)
  double overlap = 0.01;       // metres shared by neighbouring pages
  double test_square = 0.10;   // metres, the side of the cover's test square
  std::string title = "pattern";
};

struct PdfPage {
  int row = 0, column = 0;   // from the top left, 0-based
  std::string label;         // "A1": row letter, column number
  bool printed = false;      // false: no piece reaches its window
};

struct PdfSummary {
  int rows = 0, columns = 0;
  int pages = 0;               // PDF pages written, the cover included
  std::vector<PdfPage> tiles;  // rows x columns, row by row
};

// The page windows for a sheet and paper (no drawing): rows x columns and
// which of them show part of a piece.
PdfSummary tile_pages(const Layout& layout, const PdfOptions& options);

// Writes the PDF to `out` (binary). `date` (YYYY-MM-DD, may be empty) is
// the document's creation date, so that the same inputs give the same file.
// Throws OutputError where cairo fails.
PdfSummary write_pdf(std::ostream& out, const Pattern& pattern, const Layout& layout,
                     const std::vector<CutInstruction>& cut, const PdfOptions& options, const std::string& date);

}  // namespace gp
