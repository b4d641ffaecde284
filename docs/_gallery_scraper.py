"""sphinx-gallery scraper for the examples, which save their figures as PNG files."""

import os
import shutil
from pathlib import Path


class PngScraper:
    """Show the PNGs an example block wrote to ``$MBM_EXAMPLES_OUT``.

    The examples save their figures to files and close them (they run as scripts and
    in the tests), so matplotlib's own scraper sees no open figure; this one moves the
    files a block wrote into the gallery's image paths and shows them, in the order
    they were written.
    """

    def __call__(self, block, block_vars, gallery_conf):
        from sphinx_gallery.scrapers import figure_rst

        out = Path(os.environ["MBM_EXAMPLES_OUT"])
        if not out.is_dir():
            return ""
        pngs = sorted(out.glob("*.png"), key=lambda p: p.stat().st_mtime)
        names = []
        for png, dest in zip(pngs, block_vars["image_path_iterator"]):
            shutil.move(str(png), dest)
            names.append(dest)
        return figure_rst(names, gallery_conf["src_dir"])

    def __repr__(self):
        return "PngScraper"
