"""The reference profile the planner's measurements compare against: the desktop profile at 8x MSAA,
the LUTs rebuilt every frame at 15 wavelengths and the fog at 4 px froxels and 128 slices. It shares
the engine's rasterizer and the froxel method with what it measures (docs/planner.md says what that
leaves out); the sky's and the fog's own ground truths are in sky-accuracy, fog-accuracy and the
stability map."""
import copy

DESCRIPTION = "desktop at msaa8, LUTs rebuilt every frame at 15 wavelengths, fog 4 px x 128 slices"


def reference_profile(desktop):
    ref = copy.deepcopy(desktop)
    ref["name"] = "planner reference"
    ref["antialiasing"] = "msaa8"
    ref["atmosphere"]["spectral_samples"] = 15
    ref["atmosphere"]["schedule"]["full"] = True
    ref["fog"]["froxel_size_px"] = 4
    ref["fog"]["slices"] = 128
    return ref
