// synth-actions: labelled procedural stick-figure actions (no data download needed).
#include "core/tool.h"
#include "synth/actions.h"

int main(int argc, char** argv) {
  df::Tool tool(
      "synth-actions",
      "Make labelled skeleton action sequences on the 20-joint Kinect v1 skeleton (the joint\n"
      "order of UTKinect-Action3D), for the ActGAN demo and tests:\n"
      "  walk   legs and arms swing in opposition, the body moves forward and bobs\n"
      "  wave   the right arm raised to the side, the forearm swinging over the head\n"
      "  jump   crouch, take off with the arms swinging up, land\n"
      "  kick   the right leg swings forward and up, the arms counter-balance\n"
      "  squat  knees and hips bend, the body goes down with the arms forward\n"
      "and, when named, arm gestures that differ only in the right arm's path (the kind of\n"
      "classes of MSR-Action3D: many short gestures of one arm):\n"
      "  hammer, punch, side-box, throw, catch, clap (both hands), circle, draw-x, tick\n"
      "('--classes gestures' makes all nine; 'wave,gestures' ten).\n"
      "Every sequence draws its own speed (0.8-1.25x), amplitude (0.8-1.2x) and phase, and is\n"
      "performed by one of --subjects simulated bodies (sizes 0.9-1.1x; /sequences/subjects,\n"
      "for skel2h5 --test-subjects).\n"
      "\n"
      "OUTPUT: a skeleton .h5 (raw coordinates in metres, y up) for skel2h5, render-mesh.");
  tool.with_seed(0).with_force();
  df::synth::ActionParams p;
  std::string output;
  auto& app = tool.app();
  app.add_option("-o,--output", output, "Output skeleton file (.h5)")->required();
  app.add_option("--classes", p.classes,
                 "Actions to make, comma-separated (default: the first five; 'gestures': the nine "
                 "gestures)")
      ->delimiter(',');
  app.add_option("--per-class", p.per_class, "Sequences per action")->default_val(p.per_class);
  app.add_option("--frames", p.frames, "Frames per sequence")->default_val(p.frames);
  app.add_option("--fps", p.frame_rate, "Frame rate")->default_val(p.frame_rate);
  app.add_option("--subjects", p.subjects, "Simulated performers (assigned round robin)")
      ->default_val(p.subjects);
  app.add_option("--noise", p.noise, "Gaussian jitter on every coordinate (s.d., metres)")
      ->default_val(p.noise);
  tool.footer(
      "Examples:\n"
      "  synth-actions -o actions.h5\n"
      "  synth-actions --classes walk,wave --per-class 50 --frames 90 --noise 0.005 -o a.h5\n"
      "  synth-actions --classes wave,gestures --subjects 10 --frames 40 -o gestures.h5\n"
      "  render-mesh actions.h5 --sequence walk_000 --every 6 -o walk.png");
  return tool.run(argc, argv, [&] { df::synth::synth_actions(p, output, tool.common()); });
}
