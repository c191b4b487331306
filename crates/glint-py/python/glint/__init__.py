"""glint: a CPU ray tracer for learning, teaching and research, from Python.

    import glint
    scene = glint.load_file("scenes/cornell-box.toml")
    image = scene.render(spp=64)              # numpy float32, shape (height, width, 3)

Scenes load from files (``load_file``: the native TOML/JSON format or Mitsuba 3 XML, with
Mitsuba ``<default>`` parameters as keyword arguments) or from a dict with the TOML format's
schema (``load_dict``). ``Scene.render`` releases the GIL while it renders and honours Ctrl-C.
``Scene.render(samples=(a, b))`` renders samples a to b - 1 of every pixel as a ``Partial``;
``merge`` adds parts of one render into the image one render of their union gives, bit for
bit (``load_partial`` reads a part ``glint render --samples`` wrote: parts from either merge);
``glint.distributed.render`` spreads the parts over Ray tasks. ``compare`` judges an
image against a reference. A render is the command's render job: held to its limits (GLINT_MEMORY_LIMIT, 1 to 1024
threads) and checks, refused in its words (``GlintError``, ``ValueError``); what the command
warns about arrives as a ``GlintWarning``. docs/python.md has the details.
"""

from ._glint import GlintError, GlintWarning, Partial, Scene, compare, load_dict, load_file, load_partial, merge

__all__ = ["GlintError", "GlintWarning", "Partial", "Scene", "compare", "load_dict", "load_file", "load_partial", "merge"]
