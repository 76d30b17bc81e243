// render-mesh: pictures (PNG) of mesh frames and skeleton poses, without a display or GPU.
#include "apps/render_mesh.h"
#include "core/tool.h"

int main(int argc, char** argv) {
  df::Tool tool(
      "render-mesh",
      "Draw frames of meshes or skeletons into one PNG contact sheet: one row per INPUT (or\n"
      "per --sequence of it), one column per selected frame, all panels through one\n"
      "orthographic camera fitted to everything shown, so rows compare at the same scale.\n"
      "Meshes: a z-buffer rasteriser (supersampled, flat or smooth shading with a light),\n"
      "optionally coloured per vertex by a scalar with a colour bar and its units:\n"
      "  error         distance to the paired frame of --error-vs (gen-bdlstm's\n"
      "                /frames/source, else the same index), / the truth's bounding-box\n"
      "                diagonal, after removing one translation per connected part as\n"
      "                eval-metrics does (the aligned mesh is drawn);\n"
      "  deformation   |X - X_r| of the vertex's ACAP features against the reference's\n"
      "                (identity), in the file's normalized units (how the MSAE paper shows\n"
      "                deformation components);\n"
      "  displacement  |p - p_template| / the bounding-box diagonal;\n"
      "  /DATASET      a dataset of the input, shape [V] or [N,V] (e.g. a per-vertex\n"
      "                quantity of your own, added with h5import).\n"
      "Skeleton files (/poses, /skeleton/parents): stick figures, one row per sequence.\n"
      "\n"
      "INPUT: acap .h5 files (stored /frames/positions, or positions reconstructed from the\n"
      "features with the exact solver, e.g. gen-bdlstm output), mesh directories / @LISTs /\n"
      "files (OBJ, OFF, PLY, MD2), or skeleton .h5 files. All of one kind.\n"
      "OUTPUT: one .png, or a pattern with {index} (column) / {frame} (frame of the first\n"
      "row) for one PNG per selected frame, e.g. frames/{index:04d}.png, then\n"
      "  ffmpeg -i frames/%04d.png -pix_fmt yuv420p movie.mp4\n"
      "The same input gives byte-identical PNGs at any --threads.");
  tool.with_force();
  df::apps::RenderOptions opt;
  auto& app = tool.app();
  app.add_option("INPUT", opt.inputs, "Files to draw, one row each (or one per --sequence)")
      ->required();
  app.add_option("-o,--output", opt.output,
                 "PNG file, or NAME{index:04d}.png for one file per frame")
      ->required();
  app.add_option(
      "--frames", opt.frames,
      "Frames of each row: 0,5,10-20,30- (indices into the file, or into the --sequence;\n"
      "after --steps, indices into the frames it keeps), or frame names: L0.0.3,L1.2.7 (a\n"
      "components file's), stand01 (an MD2 model's). Default all");
  app.add_option("--every", opt.every, "Keep every K-th of the selected frames")
      ->check(CLI::PositiveNumber);
  app.add_option("--sequence", opt.sequences,
                 "Sequences (names or indices) to draw, one row each, frames counted from each\n"
                 "sequence's start (repeatable). Skeleton files: default all sequences")
      ->delimiter(',')
      ->allow_extra_args(false);
  app.add_option("--steps", opt.steps,
                 "Only generated frames this many steps after the last given one\n"
                 "(gen-bdlstm's /frames/step), e.g. 5,10,15")
      ->delimiter(',')
      ->allow_extra_args(false);
  app.add_option("--error-vs", opt.error_vs, "Ground truth (acap .h5 or meshes) for --color error");
  app.add_flag("--show-truth", opt.show_truth,
               "First row: the ground-truth frames paired with the first row's");
  app.add_option(
         "--color", opt.color,
         "Per-vertex colour: none, error, deformation, displacement, or a /DATASET of the input;\n"
         "auto = error with --error-vs, else none")
      ->default_val(opt.color);
  app.add_option("--colormap", opt.colormap, "viridis or jet")->default_val(opt.colormap);
  app.add_option("--range", opt.range, "Colour range LO,HI (default 0 .. the largest value shown)")
      ->delimiter(',')
      ->allow_extra_args(false);
  app.add_option("--view", opt.view, "front, side, top, back, or AZIMUTH,ELEVATION in degrees")
      ->default_val(opt.view);
  app.add_option("--up", opt.up, "The data's up axis: y or z")->default_val(opt.up);
  app.add_option("--fit", opt.fit,
                 "Fit the camera to all rows, or to the first (the truth with --show-truth;\n"
                 "other rows are clipped at the panel's edge)")
      ->default_val(opt.fit);
  app.add_option("--size", opt.width,
                 "Panel width and height in pixels (--size 320 or --height too)")
      ->default_val(opt.width);
  app.add_option("--height", opt.height, "Panel height in pixels (default: --size)");
  app.add_option("--background", opt.background, "white, black, grey or #rrggbb")
      ->default_val(opt.background);
  app.add_option("--mesh-color", opt.base_color, "Colour of uncoloured meshes (#rrggbb)")
      ->default_val(opt.base_color);
  app.add_option("--shading", opt.shading,
                 "smooth (interpolated vertex normals) or flat (face normals)")
      ->default_val(opt.shading);
  app.add_option("--supersample", opt.supersample,
                 "Anti-aliasing: samples per pixel along each axis (1-8)")
      ->default_val(opt.supersample);
  app.add_option("--row-labels", opt.row_labels,
                 "Row captions, comma-separated (default: file / sequence names)")
      ->delimiter(',')
      ->allow_extra_args(false);
  app.add_option("--column-labels", opt.column_labels,
                 "Column captions, comma-separated (default: 'frame I', or 'future frame S')")
      ->delimiter(',')
      ->allow_extra_args(false);
  app.add_option("--title", opt.title, "Title above the sheet");
  app.add_option(
      "--points", opt.points,
      "Mark vertices with red dots: a handle file (edit-shape's; the first number of each\n"
      "line is the vertex) on every mesh, or 'edit': on each input written by edit-shape\n"
      "its handles");
  tool.footer(
      "Examples:\n"
      "  render-mesh horse.h5 --every 20 -o horse.png\n"
      "  render-mesh pred.h5 linear.h5 --error-vs data.h5 --show-truth --sequence 0 --steps "
      "5,10,15 \\\n"
      "      --row-labels 'ground truth,BD-LSTM,linear' -o fig5.png   # BD-LSTM paper, Fig. 5\n"
      "  render-mesh bumps.h5 --color deformation --frames 0-4 -o bumps.png\n"
      "  render-mesh long.h5 -o frames/{index:04d}.png              # one PNG per frame\n"
      "  render-mesh actions.h5 --every 10 -o actions.png           # stick figures");
  return tool.run(argc, argv, [&] {
    if (app.count("--height") == 0) opt.height = opt.width;
    df::apps::render_mesh(opt, tool.common());
  });
}
