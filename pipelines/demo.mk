# The demo: what `make demo` runs. Data from synth-meshseq and Debian's assimp-testmodels only.
DEMO := $(OUT)/demo
FAERIE ?= /usr/share/assimp/models/MD2/faerie.md2
# The demo's MSAE (chosen on its own validation shapes, docs/msae.md): 4 level-0 components on a
# surface with 2 coarse and 8 fine planted regions, so the fine ones are left to level 1; without
# the tool's default --synthetic 16 (measured without it, and the demo's minutes are few), and
# without the tool's default start from SPLOCS (--init local): with these settings the demo's
# validation shapes choose the random start (E_rms 0.355 against 0.460; docs/msae.md).
DEMO_MSAE_ITERATIONS ?= 4500
DEMO_BUMPS := --frames 300 --resolution 24 --fine-regions 8 --seed 1
DEMO_MSAE := --split sequence --validation-fraction 0.1 --kz 4,20 --support proximal --centre-features --synthetic 0 \
  --init glorot --lr-decay-steps 1500

.PHONY: demo
demo: $(DEMO)/finger.h5 $(DEMO)/bumps.h5 $(DEMO)/flag/0000.obj \
      $(DEMO)/finger-meshes/finger-0000.obj $(DEMO)/faerie-meshes/stand01.obj \
      $(DEMO)/bdlstm-meshes/0.obj $(DEMO)/bdlstm-long.glb $(DEMO)/bdlstm-pred.json $(DEMO)/bdlstm-linear.json \
      $(DEMO)/faerie.png $(DEMO)/bdlstm-prediction.png \
      $(DEMO)/msae-components.png $(DEMO)/msae-localization.json $(DEMO)/msae-recon.json $(DEMO)/edit.png \
      $(DEMO)/actgan-generated.png $(DEMO)/actgan-mixed.png $(DEMO)/actgan-mmd.json $(DEMO)/actgan-accuracy.json \
      $(DEMO)/index.html
	@echo
	@echo "== h5check: file kinds, shapes, compression, history"
	$(BIN)/h5check --no-history $(DEMO)/faerie.h5
	@echo
	@echo "== ACAP round trips (obj2acap | acap2obj), vertex error x bounding-box diagonal"
	@sed -n 's/.*round-trip error[^:]*: /  finger (400 deg twist): /p' $(DEMO)/finger-meshes.log
	@sed -n 's/.*round-trip error[^:]*: /  faerie (MD2, 16 animations): /p' $(DEMO)/faerie-meshes.log
	@echo
	@echo "== BD-LSTM (train-bdlstm, 300 iterations on a walking finger; gen-bdlstm; eval-metrics)"
	@echo "   prediction of 15 frames from 3 initial frames on the held-out part:"
	@echo "   mean vertex error over the predicted frames, in mesh units (= relative error x the bounding-box diagonal):"
	@printf '     BD-LSTM:              %.4g  (%.4g x %.4g)\n' $$($(call json_values,$(DEMO)/bdlstm-pred.json,$(demo_vertex_error)))
	@printf '     linear extrapolation: %.4g  (%.4g x %.4g)\n' $$($(call json_values,$(DEMO)/bdlstm-linear.json,$(demo_vertex_error)))
	@echo "   (a short demo run; pipelines/bdlstm.mk trains longer and reproduces the paper's tables)"
	@echo
	@echo "== MSAE (train-msae, $(DEMO_MSAE_ITERATIONS) iterations on the bumps surface: 2 coarse + 8 fine planted regions,"
	@echo "   more than level 0's 4 components: the fine ones are left to level 1)"
	@echo "   reconstruction of the $$($(call json_values,$(DEMO)/msae-recon.json,frame_pairs)) test shapes (recon-msae; eval-metrics):"
	@printf '     E_rms x 1000 (unit ball) %.4g; relative squared error of the features: max %.4g, mean %.4g\n' \
	  $$($(call json_values,$(DEMO)/msae-recon.json,erms relative_squared_error.max relative_squared_error.mean))
	@echo "   components kept by prune-components (strength >= 0.01):"
	@for l in 0 1; do printf '     level %s: %s kept, %s dropped\n' $$l \
	  $$($(call json_values,$(DEMO)/msae-pruning.json,levels.$$l.kept levels.$$l.dropped)); done
	@echo "   where they are: per planted region the best kept component at its level (IoU of supports):"
	@sed -n '2,$$p' $(DEMO)/msae-localization.txt | sed 's/^/     /'
	@echo "   (pipelines/msae.mk trains longer, adds the baselines and reproduces the paper's tables)"
	@echo "   multiscale editing (edit-shape): a coarse region's centre raised with the level-0 components,"
	@echo "   then a fine region's with level 1 from that result (the coarse step's handles held where it put them):"
	@sed 's/^edit-shape: /     /' $(DEMO)/edit.log
	@echo
	@echo "== ActGAN (train-actgan: 400 WGAN-GP + 400 GAN iterations, small networks, on 5 synthetic actions)"
	@echo "   generated from noise vs the real test clips (eval-metrics; MMD_u^2, lower is closer):"
	@printf '     MMD_avg %.4g, MMD_seq %.4g; of motion (frame differences): MMD_avg %.4g, MMD_seq %.4g\n' \
	  $$($(call json_values,$(DEMO)/actgan-mmd.json,mmd_avg mmd_seq mmd_motion_avg mmd_motion_seq))
	@echo "   recognised by the trained classifier (classify-actions): real test clips / generated:"
	@printf '     %.3f / %.3f\n' $$($(call json_values,$(DEMO)/actgan-accuracy.json $(DEMO)/actgan-accuracy-generated.json,overall))
	@echo "   a mixture walk:0.5,wave:0.5, its class probabilities (walk wave jump kick squat; most probable):"
	@sed -n '/^sequence /,$$p' $(DEMO)/actgan-mixed.txt | sed 's/^/     /'
	@echo "   (a short demo run with small networks; train-actgan's defaults are the authors' sizes)"
	@echo
	@echo "== pictures (render-mesh)"
	@echo "  $(DEMO)/bdlstm-prediction.png   truth / BD-LSTM / linear at future frames 5, 10, 15, coloured by error"
	@echo "  $(DEMO)/faerie.png              MD2 frames above their ACAP round trip, coloured by error"
	@echo "  $(DEMO)/msae-components.png     MSAE's kept level-0 components, coloured by deformation"
	@echo "  $(DEMO)/msae-components-L1.png  the kept level-1 component that best matches each fine region"
	@echo "  $(DEMO)/edit.png                the two-step edit, handles as red dots, coloured by displacement"
	@echo "  $(DEMO)/actgan-generated.png    one generated sequence per action (stick figures, every 3rd frame)"
	@echo "  $(DEMO)/actgan-mixed.png        sequences generated for the mixture walk:0.5,wave:0.5"
	@echo
	@echo "== outputs in $(DEMO)/"
	@echo "  finger.h5, bumps.h5     synthetic sequences (acap kind, positions; bumps with ground truth)"
	@echo "  flag/                   waving flag as OBJ files"
	@echo "  finger-acap.h5          ACAP features of the finger; finger-meshes/ reconstructed from them"
	@echo "  faerie.h5               ACAP features of the MD2 faerie; faerie-meshes/ reconstructed"
	@echo "  bdlstm-model.h5         BD-LSTM trained on bdlstm-finger.h5; bdlstm-long.h5: 120 generated"
	@echo "                          frames from one initial frame, as meshes in bdlstm-meshes/ and as"
	@echo "                          bdlstm-long.glb, one animated glTF (Blender: File > Import > glTF 2.0,"
	@echo "                          then play the timeline; or drop it on any web glTF viewer)"
	@echo "  faerie.png, bdlstm-prediction.png  pictures of the round trip and the prediction (render-mesh)"
	@echo "  open the .obj files in any mesh viewer; h5dump reads the .h5 files with"
	@echo "  HDF5_PLUGIN_PATH=$(HDF5_PLUGIN_PATH) h5dump -H -p FILE"
	@echo
	@echo "== everything above on one page, the animations playing: $(abspath $(DEMO))/index.html"
	@echo "   open it with: xdg-open $(abspath $(DEMO))/index.html   (or any browser; it works offline)"

$(DEMO):
	mkdir -p $@

$(DEMO)/finger.h5: | $(DEMO)
	$(BIN)/synth-meshseq --kind finger --twist 400 --frames 120 --resolution 16 -f -o $@

$(DEMO)/bumps.h5: | $(DEMO)
	$(BIN)/synth-meshseq --kind bumps $(DEMO_BUMPS) -f -o $@

$(DEMO)/flag/0000.obj: | $(DEMO)
	$(BIN)/synth-meshseq --kind flag --frames 60 --resolution 20 -f -o $(DEMO)/flag

$(DEMO)/finger-acap.h5: $(DEMO)/finger.h5
	$(BIN)/obj2acap -f $< -o $@

$(DEMO)/finger-meshes/finger-0000.obj: $(DEMO)/finger-acap.h5
	$(BIN)/acap2obj -f $< -o $(DEMO)/finger-meshes 2>&1 | tee $(DEMO)/finger-meshes.log

$(DEMO)/faerie.h5: $(FAERIE) | $(DEMO)
	$(BIN)/obj2acap -f $< -o $@

$(DEMO)/faerie-meshes/stand01.obj: $(DEMO)/faerie.h5
	$(BIN)/acap2obj -f $< -o $(DEMO)/faerie-meshes 2>&1 | tee $(DEMO)/faerie-meshes.log

# The round trip in pictures: positions rebuilt from the features (acap2obj into an acap file, so
# frames keep their order), drawn under the MD2 frames and coloured by their distance to them.
$(DEMO)/faerie-roundtrip.h5: $(DEMO)/faerie.h5
	$(BIN)/acap2obj -q -f $< -o $@
$(DEMO)/faerie.png: $(DEMO)/faerie-roundtrip.h5 $(DEMO)/faerie.h5
	$(BIN)/render-mesh -q -f $< --error-vs $(DEMO)/faerie.h5 --show-truth --frames 0,40,80,120,160 \
	  --up z --view side --size 200 --range 0,0.001 --row-labels "MD2 frames,ACAP round trip" \
	  --title "faerie (Debian's assimp-testmodels): MD2 frames and their ACAP round trip" -o $@

# BD-LSTM: a short training run on a walking finger, a 120-frame generation as meshes, and
# prediction on the held-out part against linear extrapolation.
$(DEMO)/bdlstm-finger.h5: | $(DEMO)
	$(BIN)/synth-meshseq -q --kind finger --frames 200 --resolution 8 --periods 5 --twist 120 -f -o $(DEMO)/bdlstm-frames.h5
	$(BIN)/obj2acap -q -f $(DEMO)/bdlstm-frames.h5 -o $@

$(DEMO)/bdlstm-model.h5: $(DEMO)/bdlstm-finger.h5
	$(BIN)/train-bdlstm -f --iterations 300 --window 16 --batch 4 --print-every 100 $< -o $@

$(DEMO)/bdlstm-long.h5: $(DEMO)/bdlstm-model.h5 $(DEMO)/bdlstm-finger.h5
	$(BIN)/gen-bdlstm -q -f $^ --from 0 --length 120 -o $@

$(DEMO)/bdlstm-meshes/0.obj: $(DEMO)/bdlstm-long.h5
	$(BIN)/acap2obj -q -f $< -o $(DEMO)/bdlstm-meshes

$(DEMO)/bdlstm-long.glb: $(DEMO)/bdlstm-long.h5
	$(BIN)/export-gltf -q -f $< --fps 30 -o $@
# Reconstructed and generated sequences as animations for the report page (export-gltf).
$(DEMO)/faerie-roundtrip.glb: $(DEMO)/faerie-roundtrip.h5
	$(BIN)/export-gltf -q -f $< --fps 10 -o $@
$(DEMO)/msae-recon.glb: $(DEMO)/msae-recon.json
	$(BIN)/export-gltf -q -f $(DEMO)/msae-recon.h5 --every 4 --fps 40 -o $@
$(DEMO)/actgan-walk.glb: $(DEMO)/actgan-generated.h5
	$(BIN)/export-gltf -q -f $< --sequence walk~0 -o $@
$(DEMO)/actgan-wave.glb: $(DEMO)/actgan-generated.h5
	$(BIN)/export-gltf -q -f $< --sequence wave~0 -o $@

# The report page: every table, picture, curve and animation above (scripts/report).
DEMO_REPORTED := $(DEMO)/faerie.png $(DEMO)/faerie-roundtrip.glb $(DEMO)/bdlstm-prediction.png $(DEMO)/bdlstm-pred.json \
  $(DEMO)/bdlstm-linear.json $(DEMO)/bdlstm-long.glb $(DEMO)/msae-components.png $(DEMO)/msae-localization.json \
  $(DEMO)/msae-recon.json $(DEMO)/msae-recon.glb $(DEMO)/edit.png $(DEMO)/actgan-generated.png $(DEMO)/actgan-mixed.png \
  $(DEMO)/actgan-mmd.json $(DEMO)/actgan-accuracy.json $(DEMO)/actgan-walk.glb $(DEMO)/actgan-wave.glb
$(DEMO)/index.html: $(DEMO_REPORTED) $(DF_ROOT)/scripts/report
	$(DF_ROOT)/scripts/report $(DEMO) --kind demo --bin $(BIN) --command "make demo" -o $@

$(DEMO)/bdlstm-pred.h5: $(DEMO)/bdlstm-model.h5 $(DEMO)/bdlstm-finger.h5
	$(BIN)/gen-bdlstm -q -f $^ --test-every 4 --test-context 3 --initial 3 --length 15 -o $@

$(DEMO)/bdlstm-linear.h5: $(DEMO)/bdlstm-model.h5 $(DEMO)/bdlstm-finger.h5
	$(BIN)/gen-bdlstm -q -f $^ --test-every 4 --test-context 3 --initial 2 --method linear --length 15 -o $@

$(DEMO)/bdlstm-prediction.png: $(DEMO)/bdlstm-pred.h5 $(DEMO)/bdlstm-linear.h5 $(DEMO)/bdlstm-finger.h5
	$(BIN)/render-mesh -q -f $(DEMO)/bdlstm-pred.h5 $(DEMO)/bdlstm-linear.h5 --error-vs $(DEMO)/bdlstm-finger.h5 \
	  --show-truth --sequence 0 --steps 5,10,15 --view side --size 240 --height 140 \
	  --row-labels "ground truth,BD-LSTM (3 initial frames),linear extrapolation" \
	  --title "walking finger: prediction of held-out frames" -o $@

# The demo's printed numbers come from the tools' --json (the tables beside them are for people).
demo_vertex_error := vertex_error.mean vertex_error.mean_relative diagonal
$(DEMO)/bdlstm-%.json: $(DEMO)/bdlstm-%.h5 $(DEMO)/bdlstm-finger.h5
	$(BIN)/eval-metrics -q -f $^ --json $@ > $(@:.json=.txt)

# MSAE: a short training run on the bumps surface, its components (extracted, pruned, drawn),
# how well they find the planted regions, and the reconstruction of the held-out shapes.
$(DEMO)/bumps-acap.h5: $(DEMO)/bumps.h5
	$(BIN)/obj2acap -q -f $< -o $@
$(DEMO)/msae-model.h5: $(DEMO)/bumps-acap.h5
	$(BIN)/train-msae -f $(DEMO_MSAE) --iterations $(DEMO_MSAE_ITERATIONS) --print-every 500 $< -o $@
$(DEMO)/msae-kept.h5: $(DEMO)/msae-model.h5
	$(BIN)/extract-components -q -f $< $(DEMO)/bumps-acap.h5 -o $(DEMO)/msae-components.h5
	$(BIN)/prune-components -f $(DEMO)/msae-components.h5 -o $@ --acap $(DEMO)/msae-kept-acap.h5 \
	  --json $(DEMO)/msae-pruning.json > $(DEMO)/msae-pruning.txt
# The kept level-0 components, and the level-1 component that best matches each fine region (the
# localization's names: L<level>.<block>.<k>), one sheet each (each with its own colour range).
demo_level0 = $(call frame_names,$(DEMO)/msae-kept-acap.h5) | tr , '\n' | grep '^L0\.' | paste -sd,
demo_level1 = for r in $$(seq 0 63); do $(call json_values,$(DEMO)/msae-localization.json,regions.$$r.level regions.$$r.name) \
  2>/dev/null || break; done | awk '$$1 == 1 && !seen[$$2]++ { print $$2 }' | paste -sd,
DEMO_COMPONENTS_VIEW := --color deformation --view front --size 150 --row-labels kept
$(DEMO)/msae-components.png: $(DEMO)/msae-kept.h5 $(DEMO)/msae-localization.json
	$(BIN)/render-mesh -q -f $(DEMO)/msae-kept-acap.h5 $(DEMO_COMPONENTS_VIEW) --frames "$$($(demo_level0))" \
	  --title "MSAE level 0: the kept components of the bumps surface (colour |X - X_r| per vertex)" -o $@
	$(BIN)/render-mesh -q -f $(DEMO)/msae-kept-acap.h5 $(DEMO_COMPONENTS_VIEW) --frames "$$($(demo_level1))" \
	  --title "MSAE level 1: the kept component that best matches each fine region" -o $(DEMO)/msae-components-L1.png
$(DEMO)/msae-localization.json: $(DEMO)/msae-kept.h5 $(DEMO)/bumps.h5
	$(BIN)/eval-metrics -f $< $(DEMO)/bumps.h5 --json $@ > $(@:.json=.txt)
# Multiscale editing (paper 2, §5): the centre of the first planted (coarse) region dragged up
# with the level-0 components, then the centre of a fine one with level 1 from that result; the
# grid's corners held.
DEMO_CORNERS := 0,24,600,624
demo_region = $$($(call h5_values,$(DEMO)/bumps.h5,/synthetic/region_center) | sed -n 2p | tr -d ' ' | cut -d, -f$(1))
$(DEMO)/edit-fine.h5: $(DEMO)/msae-kept.h5 $(DEMO)/bumps.h5
	echo "$(call demo_region,1) 0 0 0.4" > $(DEMO)/edit-coarse.txt
	$(BIN)/edit-shape -f $< --handles $(DEMO)/edit-coarse.txt --relative --fixed $(DEMO_CORNERS) --levels 0 \
	  -o $(DEMO)/edit-coarse.h5 2> $(DEMO)/edit.log
	echo "$(call demo_region,3) 0 0 0.25" > $(DEMO)/edit-fine.txt
	$(BIN)/edit-shape -f $< --handles $(DEMO)/edit-fine.txt --relative --fixed $(DEMO_CORNERS) \
	  --levels 1 --from $(DEMO)/edit-coarse.h5 -o $@ 2>> $(DEMO)/edit.log
$(DEMO)/edit.png: $(DEMO)/edit-fine.h5
	$(BIN)/render-mesh -q -f $(DEMO)/edit-coarse.h5 $< --color displacement --points edit --view 30,50 \
	  --row-labels "coarse (level 0),fine (level 1)" --column-labels "edit" \
	  --title "bumps: multiscale editing with MSAE components (red: handles)" -o $@
$(DEMO)/msae-recon.json: $(DEMO)/msae-model.h5
	$(BIN)/recon-msae -q -f $< $(DEMO)/bumps-acap.h5 -o $(DEMO)/msae-recon.h5
	$(BIN)/eval-metrics -f $(DEMO)/msae-recon.h5 $(DEMO)/bumps-acap.h5 --json $@ > $(@:.json=.txt)

# ActGAN: a short training run with small networks on synthetic actions, sequences generated
# for every class and for a mixture of two, their MMD to the real test clips and how often the
# trained classifier recognises them.
$(DEMO)/actions.h5: | $(DEMO)
	$(BIN)/synth-actions -q -f --per-class 40 --frames 40 --seed 1 -o $(DEMO)/actions-raw.h5
	$(BIN)/skel2h5 -q -f $(DEMO)/actions-raw.h5 --length 30 --clip-stride 10 --test-fraction 0.2 --seed 1 -o $@
$(DEMO)/actgan-model.h5: $(DEMO)/actions.h5
	$(BIN)/train-actgan -f --hidden 64 --fc 256 --batch 16 --pretrain-iterations 400 --iterations 400 \
	  --print-every 200 $< -o $@
$(DEMO)/actgan-generated.h5: $(DEMO)/actgan-model.h5
	$(BIN)/gen-actgan -q -f --count 8 --seed 1 $< -o $@
$(DEMO)/actgan-mixed.h5: $(DEMO)/actgan-model.h5
	$(BIN)/gen-actgan -q -f --mix walk:0.5,wave:0.5 --count 3 --seed 2 $< -o $@
$(DEMO)/actgan-generated.png: $(DEMO)/actgan-generated.h5
	$(BIN)/render-mesh -q -f $< --sequence walk~0 --sequence wave~0 --sequence jump~0 --sequence kick~0 \
	  --sequence squat~0 --every 3 --size 100 --view 30,10 --title "ActGAN: actions generated from noise" -o $@
$(DEMO)/actgan-mixed.png: $(DEMO)/actgan-mixed.h5 $(DEMO)/actgan-accuracy.json
	$(BIN)/render-mesh -q -f $< --every 3 --size 100 --view 30,10 \
	  --row-labels "$$($(DF_ROOT)/scripts/classified-labels $(DEMO)/actgan-mixed.json)" \
	  --title "ActGAN: generated for the mixture walk 0.5 + wave 0.5, with the classifier's verdict" -o $@
$(DEMO)/actgan-mmd.json: $(DEMO)/actgan-generated.h5 $(DEMO)/actions.h5
	$(BIN)/eval-metrics -f $^ --json $@ > $(@:.json=.txt)
$(DEMO)/actgan-accuracy.json: $(DEMO)/actgan-model.h5 $(DEMO)/actions.h5 $(DEMO)/actgan-generated.h5 $(DEMO)/actgan-mixed.h5
	$(BIN)/classify-actions -f $< $(DEMO)/actions.h5 --json $@ > $(@:.json=.txt)
	$(BIN)/classify-actions -f $< $(DEMO)/actgan-generated.h5 --json $(DEMO)/actgan-accuracy-generated.json >> $(@:.json=.txt)
	$(BIN)/classify-actions -f --probabilities $< $(DEMO)/actgan-mixed.h5 --json $(DEMO)/actgan-mixed.json > $(DEMO)/actgan-mixed.txt
