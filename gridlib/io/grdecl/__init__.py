"""ECLIPSE GRDECL / DATA decks: ``read_grdecl`` (text in, :class:`Deck` out), ``write_grdecl`` and
``write_edit_grdecl``.

``read_grdecl`` reads what a grid needs from a GRDECL include file or a full
DATA deck (RUNSPEC, GRID, EDIT, PROPS and REGIONS sections; it stops at SOLUTION,
SUMMARY or SCHEDULE), in the syntax ECLIPSE allows as OPM Flow 2022.10 reads it
(docs/decks.md: records over lines, text after a record's ``/`` ignored to the end
of its line, the rest of a keyword's line ignored, ``--`` comments, quotes, commas,
any case):

* dimensions: DIMENS, SPECGRID; units: METRIC, FIELD, LAB, PVT-M; MAPAXES,
  MAPUNITS, GRIDUNIT (a grid in another length unit converted to the deck's);
* geometry: COORD + ZCORN, or the Cartesian keywords DX/DY/DZ (or DXV/DYV/DZV)
  with TOPS (or DEPTHZ), turned into COORD/ZCORN (DX/DY/DZ/TOPS may give the upper
  cells only, TOPS within 1e-6 m of the bottom above are snapped to it, as Flow
  does), or GDFILE (an EGRID); a binary GRDECL (:mod:`~gridlib.io.grdecl.binary`)
  read as a whole, or IMPORTed;
* ACTNUM, PORO, NTG, PERMX/Y/Z and any other array of one value per cell (or per
  cell of the current BOX) in GRID, EDIT, PROPS or REGIONS (SATNUM, FIPNUM, ...);
* FAULTS, MULTFLT, PINCH, MINPV;
* INCLUDE (relative to the DATA file's directory, as ECLIPSE and Flow; PATHS
  aliases), BOX/ENDBOX, and
  EQUALS, COPY, ADD, MULTIPLY, MINVALUE, MAXVALUE; the region operators EQUALREG,
  ADDREG, MULTIREG, COPYREG and MULTREGP, OPERATE and OPERATER;
* what modifies connections, kept as records to be replayed in the simulator's
  order (:mod:`gridlib.cornerpoint.connection_keywords`): MULTREGT (GRID and EDIT,
  deck order), GRIDOPTS, NNC, EDITNNC, and the EDIT section's TRANX/TRANY/TRANZ (the
  keywords, with BOX, and EQUALS, MULTIPLY, ADD, MINVALUE, MAXVALUE on them, in deck
  order). As OPM Flow 2022.10 reads them: MULTX/MULTX-/MULTY/... arrays in the EDIT
  section multiply the values from GRID; MULTFLT in GRID or EDIT sets a fault's
  multiplier (the last one counts); COPY from TRANX/TRANY/TRANZ is ignored (noted),
  COPY into them and operations on them in the GRID section are errors, TRANX arrays
  outside EDIT are ignored (noted); MULTNUM defaults to 1, FLUXNUM and OPERNUM have
  no default;
* repeat counts (``3*0.2``; ``5*`` leaves five values unchanged).

Other keywords of ECLIPSE and Flow (:mod:`~gridlib.io.grdecl.vocabulary`) are
skipped by the shape of their data (:mod:`~gridlib.io.grdecl.shapes`) and listed in
``Deck.notes``; a keyword outside the vocabulary is a :class:`DeckError` naming the
file, line and keyword, or with ``unknown_keywords="skip"`` skipped and listed.

Numbers are parsed in bulk (see :mod:`gridlib.io.eclipse_text`): a 1e6-cell
deck reads in about 1.5 seconds. Every error names the file, the line and the
keyword (:class:`DeckError`, an :class:`~gridlib.errors.InputError`).

``write_grdecl`` writes a deck that ECLIPSE, OPM Flow and ``read_grdecl`` read (its GRID
section, then, where the deck has one, its EDIT section: PORV, TRANX/TRANY/TRANZ
operations, EDITNNC; ``write_edit_grdecl`` writes that part alone, for a DATA deck's
EDIT section);
floats are written with the shortest text that reads back to the same float64
(Python's ``repr``) and runs of bit-identical values as ``n*v``, so a written
and re-read deck has bit-identical arrays. Each distinct value is formatted
once (``repr``, most of the time taken) and the text is assembled in NumPy,
in lines of at most 131 characters (ECLIPSE reads 132).

Lengths are in the deck's units (metres for METRIC, feet for FIELD); z is
depth, positive down, as the deck gives it.

The package: :mod:`~gridlib.io.grdecl.keywords` (the keyword loop and a handler
per keyword), :mod:`~gridlib.io.grdecl.vocabulary` and
:mod:`~gridlib.io.grdecl.shapes` (the keywords it skips, and how),
:mod:`~gridlib.io.grdecl.state` (what has been read so far),
:mod:`~gridlib.io.grdecl.read` (the deck assembled from it),
:mod:`~gridlib.io.grdecl.write` and :mod:`~gridlib.io.grdecl.edit` (the EDIT section's
text); the text of the arrays comes from :func:`gridlib.io.eclipse_text.format_values`,
written to the file block by block, and the corner-point geometry of a Cartesian deck from
:mod:`gridlib.cornerpoint.cartesian`.
"""

from ..._lazy import lazy_exports

# Imported on first use: the case checks read a deck's DIMENS (.dimens) when the workflow is
# parsed, without the reader's imports (the corner-point engine, pandas).
_EXPORTS: dict[str, str] = {
    "DeckError": "..eclipse_text",
    "SECTIONS": ".keywords",
    "UNITS": ".keywords",
    "read_grdecl": ".read",
    "write_edit_grdecl": ".write",
    "write_grdecl": ".write",
}
__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
__all__ = sorted(_EXPORTS)
