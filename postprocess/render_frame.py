"""Render one frame of a freestand ParaView series to a PNG (docs/paraview.md).

Run with ParaView's Python, headless:
    xvfb-run -a pvpython postprocess/render_frame.py SERIES -o frame.png [options]
SERIES is the series directory (or its bodies.pvd); table.pvd and contacts.pvd
next to it are shown when present.
"""

import argparse
import math
import os
import sys

from paraview import servermanager
import paraview.simple as pv

UNITS = {
    "rock_x": "rad", "rock_y": "rad", "twist": "rad",
    "slide_x": "m", "slide_y": "m", "uplift": "m",
    "velocity": "m/s", "angular_velocity": "rad/s",
}
SIGNED = {"rock_x", "rock_y", "twist", "slide_x", "slide_y", "uplift"}
CATEGORIES = {"body_id", "body_name_index", "piece"}
# Smallest half-range of a signed colour scale, so that a body at rest is not
# coloured by round-off: 1e-4 rad or 0.1 mm.
MIN_HALF_RANGE = {"rad": 1e-4, "m": 1e-4}
TEXT = [0.1, 0.1, 0.1]
TABLE_COLOUR = [0.72, 0.70, 0.66]
FORCE_COLOUR = [0.15, 0.15, 0.15]
# Longest force arrow as a fraction of the bodies' largest extent.
FORCE_ARROW_FRACTION = 0.3
# Camera direction (from the focal point): front-right, above, so rocking
# in x-z and y-z both show.
VIEW_DIRECTION = (0.75, -1.0, 0.55)
AMBIENT = 0.3


def parse_arguments(argv):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("series", help="series directory, or its bodies.pvd")
    parser.add_argument("-o", "--output", required=True, help="PNG file to write")
    which = parser.add_mutually_exclusive_group()
    which.add_argument("--time", type=float, help="time (s); the nearest frame is drawn")
    which.add_argument("--index", type=int, default=-1, help="frame index, negative from the end (default -1: last)")
    parser.add_argument("--color-by", default="rock_x",
                        help="body cell array: rock_x (default), rock_y, twist, slide_x, slide_y, uplift, "
                             "velocity, angular_velocity (magnitudes), body_name_index, body_id, piece")
    parser.add_argument("--range", type=float, nargs=2, metavar=("MIN", "MAX"),
                        help="colour range (default: this frame's, symmetric about 0 for channels)")
    parser.add_argument("--size", type=int, nargs=2, default=[1280, 720], metavar=("W", "H"), help="pixels")
    parser.add_argument("--no-forces", action="store_true", help="do not draw contact forces")
    return parser.parse_args(argv)


def series_files(series):
    directory = series if os.path.isdir(series) else os.path.dirname(os.path.abspath(series))
    bodies = series if not os.path.isdir(series) else os.path.join(directory, "bodies.pvd")
    if not os.path.isfile(bodies):
        sys.exit(f"render_frame: {bodies}: no such file")
    optional = lambda name: os.path.join(directory, name) if os.path.isfile(os.path.join(directory, name)) else None
    return bodies, optional("table.pvd"), optional("contacts.pvd")


def frame_time(reader, arguments):
    values = reader.TimestepValues  # a property: a sequence, or one number for one frame
    times = [float(t) for t in values] if hasattr(values, "__len__") else [float(values)]
    if arguments.time is not None:
        return min(times, key=lambda t: abs(t - arguments.time))
    if not -len(times) <= arguments.index < len(times):
        sys.exit(f"render_frame: frame index {arguments.index} outside the {len(times)} frames")
    return times[arguments.index]


def body_names(reader):
    data = servermanager.Fetch(reader)
    names = data.GetFieldData().GetAbstractArray("body_names")
    return [names.GetValue(i) for i in range(names.GetNumberOfValues())] if names else []


def category_label(name, value, names):
    """body_name_index counts from 0, body_id from 1; pieces have no names."""
    index = {"body_name_index": value, "body_id": value - 1}.get(name)
    return names[index] if index is not None and 0 <= index < len(names) else str(value)


def colour_bodies(display, view, reader, arguments):
    name = arguments.color_by
    if name not in reader.CellData.keys():
        sys.exit(f"render_frame: no body array '{name}'; have {', '.join(reader.CellData.keys())}")
    array = reader.CellData[name]
    vector = array.GetNumberOfComponents() > 1
    pv.ColorBy(display, ("CELLS", name, "Magnitude") if vector else ("CELLS", name))
    lut = pv.GetColorTransferFunction(name)
    lut.AutomaticRescaleRangeMode = "Never"
    bar = pv.GetScalarBar(lut, view)
    unit = UNITS.get(name)
    bar.Title = f"|{name}|" if vector else name
    bar.ComponentTitle = f"({unit})" if unit else ""
    bar.TitleColor = bar.LabelColor = TEXT
    bar.WindowLocation = "Any Location"
    bar.Position = [0.86, 0.12]
    bar.ScalarBarLength = 0.7
    bar.RangeLabelFormat = bar.LabelFormat = "%-.3g"
    bar.AutomaticLabelFormat = 0
    if name in CATEGORIES:
        names = body_names(reader)
        low, high = (int(v) for v in array.GetRange(0))
        lut.InterpretValuesAsCategories = 1
        lut.Annotations = [text for value in range(low, high + 1)
                           for text in (str(value), category_label(name, value, names))]
        lut.ApplyPreset("Brewer Qualitative Set1", True)
        bar.Title = "body" if name != "piece" else "piece"
        bar.ComponentTitle = ""
    else:
        lut.ApplyPreset("Cool to Warm" if name in SIGNED else "Viridis (matplotlib)", True)
        if arguments.range:
            low, high = arguments.range
        elif name in SIGNED:
            half = max(abs(v) for v in array.GetRange(0))
            half = max(half, MIN_HALF_RANGE[UNITS[name]])
            low, high = -half, half
        else:
            low, high = array.GetRange(-1 if vector else 0)
            high = max(high, low + 1e-12)
        lut.RescaleTransferFunction(low, high)
    display.SetScalarBarVisibility(view, True)


def paint(display, colour):
    """One solid colour, whatever arrays the data carry."""
    display.ColorArrayName = ["POINTS", ""]
    display.AmbientColor = display.DiffuseColor = colour


def soften_shadows(display):
    """Some ambient light, so that faces turned from the headlight keep their colour."""
    display.Ambient = AMBIENT
    display.Diffuse = 1.0 - AMBIENT


def show_forces(contacts_file, time, view, extent):
    contacts = pv.PVDReader(FileName=contacts_file)
    contacts.UpdatePipeline(time)
    if "force" not in contacts.PointData.keys() or contacts.GetDataInformation().GetNumberOfPoints() == 0:
        return
    largest = contacts.PointData["force"].GetRange(-1)[1]
    if largest <= 0:
        return
    arrows = pv.Glyph(Input=contacts, GlyphType="Arrow")
    arrows.OrientationArray = ["POINTS", "force"]
    arrows.ScaleArray = ["POINTS", "force"]
    arrows.ScaleFactor = FORCE_ARROW_FRACTION * extent / largest
    arrows.GlyphMode = "All Points"
    paint(pv.Show(arrows, view), FORCE_COLOUR)


def place_camera(view, bounds):
    centre = [(bounds[2 * i] + bounds[2 * i + 1]) / 2 for i in range(3)]
    norm = math.sqrt(sum(c * c for c in VIEW_DIRECTION))
    view.CameraFocalPoint = centre
    view.CameraPosition = [c + d / norm for c, d in zip(centre, VIEW_DIRECTION)]
    view.CameraViewUp = [0, 0, 1]
    view.ResetCamera(*bounds)  # keeps the direction, fits the bodies


def main(argv):
    arguments = parse_arguments(argv)
    bodies_file, table_file, contacts_file = series_files(arguments.series)

    view = pv.CreateView("RenderView")
    view.ViewSize = arguments.size
    view.OrientationAxesVisibility = 1
    view.UseColorPaletteForBackground = 0
    view.Background = [1, 1, 1]

    bodies = pv.PVDReader(FileName=bodies_file)
    time = frame_time(bodies, arguments)
    view.ViewTime = time
    bodies.UpdatePipeline(time)
    body_display = pv.Show(bodies, view)
    body_display.Representation = "Surface With Edges"
    body_display.EdgeColor = [0.2, 0.2, 0.2]
    soften_shadows(body_display)
    colour_bodies(body_display, view, bodies, arguments)
    bounds = bodies.GetDataInformation().GetBounds()
    extent = max(bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4])

    if table_file:
        table = pv.PVDReader(FileName=table_file)
        table_display = pv.Show(table, view)
        paint(table_display, TABLE_COLOUR)
        soften_shadows(table_display)
    if contacts_file and not arguments.no_forces:
        show_forces(contacts_file, time, view, extent)

    label = pv.Text(Text=f"t = {time:.3f} s")
    label_display = pv.Show(label, view)
    label_display.Color = TEXT
    label_display.WindowLocation = "Upper Left Corner"

    place_camera(view, bounds)
    # Written under a temporary name and renamed: an older PNG survives a failure.
    part = arguments.output + ".part.png"
    pv.SaveScreenshot(part, view, ImageResolution=arguments.size)
    os.replace(part, arguments.output)
    print(f"render_frame: t = {time} s -> {arguments.output}")


if __name__ == "__main__":
    main(sys.argv[1:])
