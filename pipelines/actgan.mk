# ActGAN experiments (paper 3: Wang et al., "Learning Diverse Stochastic Human-Action Generators
# by Learning Smooth Latent Transitions"), on the data we have:
#   make -f Makefile.data actgan [DATA=../shared/data] [OUT=out] [AG_SETS="synthetic"] [-j2]
# Per data set S (synthetic: synth-actions, 5 classes, 6 simulated subjects, subjects 5 and 6
# held out; gestures: synth-actions' 10 arm gestures (MSR-Action3D's kind of classes), 10
# subjects, clips of 20 frames at 15 fps as MSR's, subjects 2, 4, 6, 8, 10 held out; utkinect:
# UTKinect-Action3D from DATA, 10 classes, subjects 2, 4, 6, 8, 10 held out):
#   $(AG)/S/mmd.md        MMD_avg and MMD_seq of 100 generated sequences per class against the
#                         real test clips, and the same of their frame differences (motion): the
#                         real training clips (the data's own level), ours, the direct-pose RNN
#                         baseline, the ablations of paper Tables 5-6 (smoothness none / latent
#                         only / both, direct latent, no classifier) and ours in the paper's form
#   $(AG)/S/recognition.md  FID, diversity, multimodality and accuracy (Action2Motion / ACTOR / MDM)
#                         in the features of a recogniser trained alone on the real training clips
#                         (train-actgan --classifier-only, a 30-wide head): the real test clips'
#                         own values, the real training clips, ours, the baseline, the ablations
#   $(AG)/S/accuracy.md   per class, how often a classifier recognises real test clips and
#                         generated sequences: ours (trained inside the GAN) and a classifier
#                         trained alone on the real clips (paper Table 2's Baseline_T/G)
#   $(AG)/S/mixed.png     sequences generated for a mixture of two classes (+ mixed.md: the
#                         classifier's probabilities)
#   $(AG)/S/latent.png    2-D latent trajectories of a model with --latent 2, per class (Fig. 3)
#   $(AG)/S/generated.png one generated sequence per class, stick figures
#   $(AG)/S/curve.png     the loss terms over training
# Training times on 2 cores are in the README (ActGAN section). AG_PRETRAIN / AG_ITERATIONS set
# the iteration counts and AG_OPTIONS adds options to every model (a smoke run:
# AG_PRETRAIN=10 AG_ITERATIONS=10 AG_OPTIONS="--hidden 16 --fc 32 --batch 8" AG_COUNT=10).
AG := $(OUT)/actgan
HAVE_UTK := $(wildcard $(DATA)/skeleton/UTKinect.tar.zst)
AG_SETS ?= synthetic gestures $(if $(HAVE_UTK),utkinect)
# train-actgan's default pre-training (the count of the curve's pre-training part below)
AG_PRETRAIN ?= 1000
# The GAN's discriminator and iteration count, chosen on the validation part (actgan-validation,
# synthetic, subject 4 held out; README): with the paper's BiLSTM discriminator (binary
# cross-entropy) the GAN phase moved the sequences away from the data in every setting tried; a
# Wasserstein critic of whole clips with the gradient penalty holds them at the data's level and
# its held-out curves stop improving at about 600 GAN iterations on synthetic actions (flat to
# 2,300) and at 800 on UTKinect (subject 9 held out; every measure's minimum there). That critic
# with 5 critic steps is train-actgan's default since stop 76 (with Omega's pose term only and
# h_1 ~ N(0, I); --paper-form: the BiLSTM, both terms, U(-1, 1)), so every model here trains with
# the tool's defaults; the direct-pose baseline and the ablations against the same critic. So is
# the GAN's iteration count since stop 76: 800 on every set (the count issue 71's three
# validation sets measured the defaults at; synthetic actions had 600 here before). AG_GAN adds
# options to every model; AG_ITERATIONS, when set, is every model's GAN iteration count.
AG_CRITIC := --discriminator critic --d-steps 5
AG_GAN ?=
AG_ITERATIONS ?=
# what the tables say of the count
ag_iterations = $(or $(AG_ITERATIONS),train-actgan's default number of)
AG_OPTIONS ?=
AG_COUNT ?= 100
AG_VARIANTS := pose no-smooth latent-only both-smooth direct no-cls paper
pose_AG := --generator pose
no-smooth_AG := --smoothness none
latent-only_AG := --smoothness latent
both-smooth_AG := --smoothness both
direct_AG := --direct-latent
no-cls_AG := --no-classifier
paper_AG := --paper-form
latent2_AG := --latent 2
cls-alone_AG := --classifier-only
# The recogniser of recognition.md: a classifier trained alone on the real training clips, its head
# 30 wide as Action2Motion's recogniser (FID's covariances are then estimable from a few hundred clips)
recogniser_AG := --classifier-only --hidden 128 --fc 30
# Ours and the baseline again at other training seeds (seedN, pose-seedN; seeds.md): how much of a
# difference between the two is one training run's luck. AG_SEEDS= leaves them out.
AG_SEEDS ?= 2 3 4 5
AG_SEED_MODELS := $(foreach n,$(AG_SEEDS),seed$(n) pose-seed$(n))
$(foreach n,$(AG_SEEDS),$(eval seed$(n)_AG := --seed $(n))$(eval pose-seed$(n)_AG := --generator pose --seed $(n)))
# $(call ag_train,VARIANT): a model's training options in a rule of set $* (no pre-training without a
# decoder to train,
# and the recogniser, an instrument, keeps its own size when AG_OPTIONS shrinks the models)
ag_train = --pretrain-iterations $(if $(filter pose% cls-alone recogniser,$(1)),0,$(AG_PRETRAIN)) \
  $(if $(AG_ITERATIONS),--iterations $(AG_ITERATIONS)) $(AG_GAN) $(if $(filter recogniser,$(1)),,$(AG_OPTIONS)) $(if $(1),$($(1)_AG))
# The training subjects (the data's own level in mmd.md: their real clips against the test clips)
synthetic_TRAIN_SUBJECTS := 1,2,3,4
gestures_TRAIN_SUBJECTS := 1,3,5,7,9
utkinect_TRAIN_SUBJECTS := 1,3,5,7,9
synthetic_MIX := walk:0.5,wave:0.5
gestures_MIX := wave:0.5,punch:0.5
utkinect_MIX := walk:0.5,waveHands:0.5
AG_LABEL_ours := ours (the defaults: residual latent from h_1 ~ N(0, I), smoothness on poses, classifier, the critic)
AG_LABEL_pose := direct-pose RNN baseline (no latent transitions, no decoder)
AG_LABEL_no-smooth := ours, no smoothness (Table 5)
AG_LABEL_latent-only := ours, smoothness on latents only (Table 5)
AG_LABEL_both-smooth := ours, smoothness on latents and poses (the paper's Omega; Table 5)
AG_LABEL_direct := ours, direct latent (Table 6)
AG_LABEL_no-cls := ours, no classifier (Table 2 ablation)
AG_LABEL_paper := ours in the paper's form (--paper-form: the BiLSTM discriminator, 1 step, smoothness on both, h_1 ~ U(-1, 1))

.PHONY: actgan
actgan: $(foreach s,$(AG_SETS),$(AG)/$(s)/mmd.md $(if $(AG_SEEDS),$(AG)/$(s)/seeds.md) $(AG)/$(s)/recognition.md $(AG)/$(s)/accuracy.md $(AG)/$(s)/mixed.png \
          $(AG)/$(s)/latent.png $(AG)/$(s)/generated.png $(AG)/$(s)/curve.png $(AG)/$(s)/gen.glb $(AG)/$(s)/mixed.glb)
	@for s in $(AG_SETS); do \
	  echo; echo "=== $$s"; cat $(AG)/$$s/mmd.md; echo; $(if $(AG_SEEDS),cat $(AG)/$$s/seeds.md; echo;) cat $(AG)/$$s/recognition.md; echo; cat $(AG)/$$s/accuracy.md; echo; cat $(AG)/$$s/mixed.md; \
	  echo; echo "pictures: $(AG)/$$s/generated.png, mixed.png, latent.png, curve.png"; \
	done
	$(call pipeline_report,$(AG),actgan)

# --- data: equal-length normalized clips with a subject split
$(AG)/synthetic/data.h5:
	@mkdir -p $(@D)
	$(BIN)/synth-actions -q -f --per-class 60 --frames 60 --subjects 6 --seed 1 -o $(@D)/raw.h5
	$(BIN)/skel2h5 -q -f $(@D)/raw.h5 --length 30 --clip-stride 10 --test-subjects 5,6 -o $@
$(AG)/gestures/data.h5:
	@mkdir -p $(@D)
	$(BIN)/synth-actions -q -f --classes wave,gestures --per-class 20 --frames 60 --subjects 10 --noise 0.01 --seed 1 -o $(@D)/raw.h5
	$(BIN)/skel2h5 -q -f $(@D)/raw.h5 --fps 15 --length 20 --clip-stride 5 --test-subjects 2,4,6,8,10 -o $@
$(eval $(call UNPACK_RULES,$(AG)/utkinect/src,$(DATA)/skeleton/UTKinect.tar.zst))
$(AG)/utkinect/data.h5: $(AG)/utkinect/src/.unpacked
	$(BIN)/skel2h5 -q -f $(AG)/utkinect/src/UTKinect/joints --fps 15 --length 20 --clip-stride 5 \
	  --test-subjects 2,4,6,8,10 -o $@

# --- models: ours, the variants, a 2-D latent model for the plot, the classifier alone
# Beside each model its options, rewritten only when they change: a model retrains when its
# options do (new iteration counts, say), and only then.
$(AG)/%/model.args: FORCE
	@mkdir -p $(@D)
	@echo '$(call ag_train,)' $(write_if_changed)
$(AG)/%/model.h5: $(AG)/%/data.h5 $(AG)/%/model.args
	$(call launch,train) $(BIN)/train-actgan -f --threads $(TRAIN_THREADS) --print-every 100 --checkpoint-every 200 --resume \
	  $(call ag_train,) $< -o $@ 2>&1 | tee $(@:.h5=.log)
define AG_VARIANT_RULES
$(AG)/%/model-$(1).args: FORCE
	@mkdir -p $$(@D)
	@echo '$$(call ag_train,$(1))' $$(write_if_changed)
$(AG)/%/model-$(1).h5: $(AG)/%/data.h5 $(AG)/%/model-$(1).args
	$$(call launch,train) $$(BIN)/train-actgan -f --threads $$(TRAIN_THREADS) --print-every 100 --checkpoint-every 200 --resume \
	  $$(call ag_train,$(1)) $$< -o $$@ 2>&1 | tee $$(@:.h5=.log)
endef
$(foreach v,$(AG_VARIANTS) latent2 cls-alone recogniser $(AG_SEED_MODELS),$(eval $(call AG_VARIANT_RULES,$(v))))

# --- generation and measures
$(AG)/%/gen.h5: $(AG)/%/model.h5
	$(call launch,generate) $(BIN)/gen-actgan -q -f --count $(AG_COUNT) --seed 7 $< -o $@
define AG_GEN_RULES
$(AG)/%/gen-$(1).h5: $(AG)/%/model-$(1).h5
	$$(call launch,generate) $$(BIN)/gen-actgan -q -f --count $$(AG_COUNT) --seed 7 $$< -o $$@
endef
$(foreach v,$(AG_VARIANTS) $(AG_SEED_MODELS),$(eval $(call AG_GEN_RULES,$(v))))
# S/NAME.mmd.json: every measure of S/NAME.h5 against the real test clips in one eval-metrics run
# — MMD, motion, variety, pace and the recogniser's (mmd.md and recognition.md read it); real: the
# real training clips (the data's own level)
define AG_EVAL_RULES
$(AG)/$(1)/%.mmd.json: $(AG)/$(1)/%.h5 $(AG)/$(1)/model-recogniser.h5 $(AG)/$(1)/data.h5
	$$(call launch,eval) $$(BIN)/eval-metrics -q -f $$< $(AG)/$(1)/data.h5 --recogniser $(AG)/$(1)/model-recogniser.h5 --json $$@.tmp > /dev/null && mv $$@.tmp $$@
$(AG)/$(1)/real.mmd.json: $(AG)/$(1)/data.h5 $(AG)/$(1)/model-recogniser.h5
	$$(call launch,eval) $$(BIN)/eval-metrics -q -f $$< $$< --pred-subjects $$($(1)_TRAIN_SUBJECTS) --recogniser $(AG)/$(1)/model-recogniser.h5 --json $$@.tmp > /dev/null && mv $$@.tmp $$@
endef
$(foreach s,$(AG_SETS),$(eval $(call AG_EVAL_RULES,$(s))))
ag_mmd = $(call json_values,$(1),mmd_$(2)) | awk '{ printf "%.4f", $$1 }'
ag_mmd_row = $$($(call ag_mmd,$(1),avg)) | $$($(call ag_mmd,$(1),seq)) | $$($(call ag_mmd,$(1),motion_avg)) | $$($(call ag_mmd,$(1),motion_seq))
# variety: the mean distance between two sequences of a class over the real test clips' (1: as
# varied as the data; eval-metrics' pairwise_ratio, averaged over the classes)
ag_variety = $$($(call json_values,$(1),pairwise_ratio) | awk '{ printf "%.3f", $$1 }')
# pace: the distance a pose moves per frame over the real test clips' (eval-metrics' pace_ratio)
ag_pace = $$($(call json_values,$(1),pace_ratio) | awk '{ printf "%.3f", $$1 }')
# $(call ag_gen_json,SET,MODEL): the measures of a model's generated sequences (ours: gen.mmd.json)
ag_gen_json = $(AG)/$(1)/gen$(if $(filter ours,$(2)),,-$(2)).mmd.json
$(AG)/%/mmd.md: $(AG)/%/gen.mmd.json $(foreach v,$(AG_VARIANTS),$(AG)/%/gen-$(v).mmd.json) $(AG)/%/real.mmd.json
	{ echo "$* — MMD_u^2 (max over bandwidths) of $(AG_COUNT) generated sequences per class against the real test clips (lower is closer; paper Tables 1, 5, 6); motion: the same of frame differences; variety: see below the table. Every model but the paper's form trained against the same discriminator ($(or $(AG_GAN),train-actgan's default: a Wasserstein critic of whole clips, 5 critic steps)), $(ag_iterations) GAN iterations."; echo; \
	  echo "| model | MMD_avg | MMD_seq | motion MMD_avg | motion MMD_seq | variety | pace |"; echo "|---|---:|---:|---:|---:|---:|---:|"; \
	  echo "| the real training clips (subjects $($*_TRAIN_SUBJECTS): the data's own level) | $(call ag_mmd_row,$(AG)/$*/real.mmd.json) | $(call ag_variety,$(AG)/$*/real.mmd.json) | $(call ag_pace,$(AG)/$*/real.mmd.json) |"; \
	  $(foreach v,ours $(AG_VARIANTS),echo "| $(AG_LABEL_$(v)) | $(call ag_mmd_row,$(call ag_gen_json,$*,$(v))) | $(call ag_variety,$(call ag_gen_json,$*,$(v))) | $(call ag_pace,$(call ag_gen_json,$*,$(v))) |";) \
	  echo; echo "variety: per class, the mean distance between two generated sequences over that of two real test clips, averaged over the classes (1: as varied as the data; per class in gen*.mmd.json, eval-metrics' variety table). pace: per class, the mean distance a pose moves from one frame to the next over the real test clips', averaged over the classes (1: the data's pace). The classifier's view of the same: accuracy.md."; \
	} $(write_if_changed)
# seeds.md: ours against the baseline at training seed 1 (the models above) and AG_SEEDS, then per
# measure the mean, the range and at how many seeds ours is lower.
# $(call ag_seed_model,VARIANT,SEED): the model's name in gen-NAME ('' = ours at seed 1)
ag_seed_model = $(if $(filter 1,$(2)),$(1),$(1:%=%-)seed$(2))
ag_seed_json = $(AG)/$(1)/gen$(patsubst %,-%,$(call ag_seed_model,$(2),$(3))).mmd.json
$(AG)/%/seeds.md: $(foreach n,1 $(AG_SEEDS),$(call ag_seed_json,%,,$(n)) $(call ag_seed_json,%,pose,$(n)))
	rows=$$($(foreach n,1 $(AG_SEEDS),echo "| $(n) | $(call ag_mmd_row,$(call ag_seed_json,$*,,$(n))) | $(call ag_mmd_row,$(call ag_seed_json,$*,pose,$(n))) |";)); \
	{ echo "$* — ours against the $(AG_LABEL_pose) at training seeds 1 $(AG_SEEDS) (seed 1: mmd.md's models; generation seed 7, $(AG_COUNT) sequences per class, the real test clips)"; echo; \
	  echo "| training seed | ours MMD_avg | MMD_seq | motion MMD_avg | motion MMD_seq | baseline MMD_avg | MMD_seq | motion MMD_avg | motion MMD_seq |"; \
	  echo "|---:|---:|---:|---:|---:|---:|---:|---:|---:|"; echo "$$rows"; echo; \
	  echo "| over the seeds | ours: mean (lowest - highest) | baseline: mean (lowest - highest) | ours lower at |"; echo "|---|---:|---:|---:|"; \
	  echo "$$rows" | awk -F'|' '{ n++; for (c = 3; c <= 10; c++) { s[c] += $$c; \
	    if (n == 1 || $$c < lo[c]) lo[c] = $$c; if (n == 1 || $$c > hi[c]) hi[c] = $$c } \
	    for (c = 3; c <= 6; c++) if ($$c < $$(c + 4)) w[c]++ } \
	  END { split("MMD_avg,MMD_seq,motion MMD_avg,motion MMD_seq", m, ","); for (c = 3; c <= 6; c++) \
	    printf "| %s | %.4f (%.4f - %.4f) | %.4f (%.4f - %.4f) | %d of %d seeds |\n", \
	      m[c - 2], s[c] / n, lo[c], hi[c], s[c + 4] / n, lo[c + 4], hi[c + 4], w[c], n }'; \
	} $(write_if_changed)

# $(call ag_acc_of,JSON,CLASS): a class's accuracy in classify-actions' JSON (CLASS a shell word;
# "all": the overall accuracy).
ag_acc_of = p=accuracy.$(2).accuracy; [ $(2) = all ] && p=overall; \
  $(BIN)/collect-metrics --values --columns $$p $(1) | awk '{ printf "%.3f", $$1 }'
$(AG)/%/accuracy.md: $(AG)/%/model.h5 $(AG)/%/model-cls-alone.h5 $(AG)/%/gen.h5 $(AG)/%/data.h5
	$(BIN)/classify-actions -f $(AG)/$*/model.h5 $(AG)/$*/data.h5 --json $(AG)/$*/acc-ours-real.json > $(AG)/$*/acc-ours-real.txt
	$(BIN)/classify-actions -f $(AG)/$*/model.h5 $(AG)/$*/gen.h5 --json $(AG)/$*/acc-ours-gen.json > $(AG)/$*/acc-ours-gen.txt
	$(BIN)/classify-actions -f $(AG)/$*/model-cls-alone.h5 $(AG)/$*/data.h5 --json $(AG)/$*/acc-alone-real.json > $(AG)/$*/acc-alone-real.txt
	$(BIN)/classify-actions -f $(AG)/$*/model-cls-alone.h5 $(AG)/$*/gen.h5 --json $(AG)/$*/acc-alone-gen.json > $(AG)/$*/acc-alone-gen.txt
	{ echo "$* — classification accuracy per class (paper Table 2): real test clips (T) and our generated sequences (G)"; echo; \
	  echo "| class | Baseline_T | Baseline_G | Ours_T | Ours_G |"; echo "|---|---:|---:|---:|---:|"; \
	  for c in $$($(call h5_values,$(AG)/$*/data.h5,/classes/names) | grep -o '"[^"]*"' | tr -d '"') all; do \
	    echo "| $$c | $$($(call ag_acc_of,$(AG)/$*/acc-alone-real.json,$$c)) | $$($(call ag_acc_of,$(AG)/$*/acc-alone-gen.json,$$c)) | $$($(call ag_acc_of,$(AG)/$*/acc-ours-real.json,$$c)) | $$($(call ag_acc_of,$(AG)/$*/acc-ours-gen.json,$$c)) |"; \
	  done; } $(write_if_changed)

# recognition.md: the measures of the field (Action2Motion, ACTOR, MDM) in the recogniser's features,
# from the same JSON files as mmd.md.
# $(call ag_rec_row,JSON,WHICH): FID | diversity | multimodality | accuracy of WHICH (generated: PRED,
# real: the real test clips themselves, FID one half against the other)
ag_rec_row = $$($(call json_values,$(1),recognition.$(2).fid recognition.$(2).diversity recognition.$(2).multimodality recognition.$(2).accuracy) | \
  awk '{ printf "%.3f | %.3f | %.3f | %.3f", $$1, $$2, $$3, $$4 }')
$(AG)/%/recognition.md: $(AG)/%/gen.mmd.json $(foreach v,$(AG_VARIANTS),$(AG)/%/gen-$(v).mmd.json) $(AG)/%/real.mmd.json
	{ echo "$* — in the features of a recogniser trained alone on the real training clips (train-actgan $(recogniser_AG), $(ag_iterations) iterations; its 30 features are what its output layer reads): FID of $(AG_COUNT) generated sequences per class against the real test clips, diversity (mean feature distance of 200 random pairs), multimodality (of 20 random pairs within a class, averaged over the classes) and the recogniser's accuracy, as Action2Motion, ACTOR and MDM report them (each pair measure the mean of 10 draws; eval-metrics --recogniser). Lower FID is closer to the data; diversity and multimodality are closest to the real test clips' own."; echo; \
	  echo "| model | FID | diversity | multimodality | accuracy |"; echo "|---|---:|---:|---:|---:|"; \
	  echo "| the real test clips (the reference: FID of one half against the other) | $(call ag_rec_row,$(AG)/$*/real.mmd.json,real) |"; \
	  echo "| the real training clips (subjects $($*_TRAIN_SUBJECTS)) | $(call ag_rec_row,$(AG)/$*/real.mmd.json,generated) |"; \
	  $(foreach v,ours $(AG_VARIANTS),echo "| $(AG_LABEL_$(v)) | $(call ag_rec_row,$(call ag_gen_json,$*,$(v)),generated) |";) \
	} $(write_if_changed)

# A generated sequence (the first class's first) and a mixture's, as animated joints for the report page.
$(AG)/%/gen.glb: $(AG)/%/gen.h5
	$(BIN)/export-gltf -q -f $< --sequence 0 -o $@
$(AG)/%/mixed.glb: $(AG)/%/mixed.png
	$(BIN)/export-gltf -q -f $(AG)/$*/mixed.h5 --sequence 0 -o $@

# --- pictures
$(AG)/%/generated.png: $(AG)/%/gen.h5
	$(BIN)/render-mesh -q -f $< $$($(call h5_values,$<,/classes/names) | grep -o '"[^"]*"' | tr -d '"' | sed 's/.*/--sequence &~0/') \
	  --every 3 --size 100 --view 30,10 --title "$*: one generated sequence per class (every 3rd frame)" -o $@
$(AG)/%/mixed.png: $(AG)/%/model.h5
	$(BIN)/gen-actgan -q -f --mix $($*_MIX) --count 3 --seed 8 $< -o $(AG)/$*/mixed.h5
	$(BIN)/classify-actions -f --probabilities $< $(AG)/$*/mixed.h5 --json $(AG)/$*/mixed.json | sed -n '/^sequence/,$$p' > $(AG)/$*/mixed.md
	$(BIN)/render-mesh -q -f $(AG)/$*/mixed.h5 --every 3 --size 100 --view 30,10 \
	  --row-labels "$$($(DF_ROOT)/scripts/classified-labels $(AG)/$*/mixed.json)" \
	  --title "$*: generated for the mixture $($*_MIX), each with the trained classifier's verdict" -o $@
$(AG)/%/latent.png: $(AG)/%/model-latent2.h5
	$(BIN)/gen-actgan -q -f --count 5 --seed 9 --latents $(AG)/$*/latent.tsv $< -o $(AG)/$*/latent.h5
	rm -f $(AG)/$*/latent-*.txt
	awk -F'\t' '/^#/ || !NF { next } { split($$1, a, "~"); f = "$(AG)/$*/latent-" a[1] ".txt"; \
	  if ($$1 != seen[f]) { if (seen[f] != "") print "" > f; seen[f] = $$1 } print $$3, $$4 > f }' $(AG)/$*/latent.tsv
	gnuplot -e "set terminal pngcairo size 760,600; set output '$@'; set key outside right; \
	  set linetype 9 lc rgb '#8c564b'; set linetype 10 lc rgb '#e377c2'; set linetype 11 lc rgb '#7f7f7f'; \
	  set linetype 12 lc rgb '#bcbd22'; set linetype cycle 12; \
	  set title '$*: 2-D latent trajectories h_t of one model, 5 per class (paper Fig. 3)'; \
	  files = system('ls $(AG)/$*/latent-*.txt'); \
	  plot for [f in files] f using 1:2 with lines title system('basename '.f.' .txt | sed s/latent-//')"
$(AG)/%/curve.png: $(AG)/%/model.h5
	$(call h5_values,$<,/training/log,%.6g) | tr -c '0-9.e+\n-' ' ' | xargs -n 7 > $(@:.png=.txt)
	gnuplot -e "set terminal pngcairo size 800,500; set output '$@'; \
	  set title '$*: ActGAN training (to $(AG_PRETRAIN): the pre-training critic; after: the GAN)'; set xlabel 'iteration'; \
	  plot '$(@:.png=.txt)' using 1:3 with linespoints title 'discriminator / critic loss', \
	       '' using 1:4 with linespoints title 'adversarial (G) / Wasserstein estimate', \
	       '' using 1:5 with linespoints title 'smoothness', '' using 1:6 with linespoints title 'cycle (classifier CE)'"

# --- validation: the GAN's iteration count chosen on training subjects held out of training
#   make -f Makefile.data actgan-validation [AG_SETS=...]
# Ours, ours with the decoder fixed in the GAN phase (--freeze-decoder, as the authors' code), with
# sigma1 as the authors' code weighs it (their latent term is summed over the batch, not averaged:
# 0.05 x our batch of 32 = 1.6; their code's 0.1 x their batch of 64 = 6.4), the generator's steps
# starting small (--step-init small), the discriminator as the authors' code has it (frames and
# their differences, every step to its head; each alone and both), a 5x lower learning rate with
# some of these, instance noise on the discriminator's frames (--disc-noise), no classifier, a
# discriminator slower than the generator (--disc-lr), a Wasserstein critic of whole clips with
# the gradient penalty (--discriminator critic) and the direct-pose baseline (against the BiLSTM
# and against that critic) train AG_VAL_ITERATIONS GAN iterations without the clips of
# S_VAL_SUBJECTS (training subjects: the test part is never looked at); every 100 iterations the
# log gets the MMD_avg / MMD_seq of 100 generated sequences per class against those clips.
# $(AG)/S/validation.md: per model the minimum of each (and where), the last value, and the
# size of its generated poses at the first and the last frame (scripts/pose-norms);
# $(AG)/S/validation.png: the curves. train-actgan's GAN iteration count is set from where they stop falling.
AG_VAL_ITERATIONS ?= 1000
AG_VAL_MODELS := ours ours-frozen ours-frozen-s1.6 ours-s6.4 ours-frozen-s6.4 ours-small ours-small-s6.4 \
  ours-lr2e-5 ours-small-lr2e-5 ours-dmotion ours-dmotion-lr2e-5 ours-dall ours-dauthors ours-dauthors-lr2e-5 \
  ours-noise0.1 ours-noise0.3 ours-nocls ours-dlr1e-5 ours-nocls-dlr1e-5 ours-critic ours-critic-normal pose pose-critic
synthetic_VAL_SUBJECTS := 4
gestures_VAL_SUBJECTS := 9
utkinect_VAL_SUBJECTS := 9
# The data's own level: the real clips of the other training subjects against the held-out ones,
# the score of a generator that reproduced its training clips exactly (eval-metrics --pred-subjects).
synthetic_VAL_REF_SUBJECTS := 1,2,3
gestures_VAL_REF_SUBJECTS := 1,3,5,7
utkinect_VAL_REF_SUBJECTS := 1,3,5,7
ours_VAL := --pretrain-iterations $(AG_PRETRAIN)
ours-frozen_VAL := --pretrain-iterations $(AG_PRETRAIN) --freeze-decoder
ours-frozen-s1.6_VAL := --pretrain-iterations $(AG_PRETRAIN) --freeze-decoder --sigma1 1.6
ours-s6.4_VAL := --pretrain-iterations $(AG_PRETRAIN) --sigma1 6.4
ours-frozen-s6.4_VAL := --pretrain-iterations $(AG_PRETRAIN) --freeze-decoder --sigma1 6.4
ours-small_VAL := --pretrain-iterations $(AG_PRETRAIN) --step-init small
ours-small-s6.4_VAL := --pretrain-iterations $(AG_PRETRAIN) --step-init small --sigma1 6.4
ours-lr2e-5_VAL := --pretrain-iterations $(AG_PRETRAIN) --lr 2e-5
ours-small-lr2e-5_VAL := --pretrain-iterations $(AG_PRETRAIN) --step-init small --lr 2e-5
ours-dmotion_VAL := --pretrain-iterations $(AG_PRETRAIN) --disc-input motion
ours-dmotion-lr2e-5_VAL := --pretrain-iterations $(AG_PRETRAIN) --disc-input motion --lr 2e-5
ours-dall_VAL := --pretrain-iterations $(AG_PRETRAIN) --disc-pool all
ours-dauthors_VAL := --pretrain-iterations $(AG_PRETRAIN) --disc-input motion --disc-pool all
ours-dauthors-lr2e-5_VAL := --pretrain-iterations $(AG_PRETRAIN) --disc-input motion --disc-pool all --lr 2e-5
ours-noise0.1_VAL := --pretrain-iterations $(AG_PRETRAIN) --disc-noise 0.1
ours-noise0.3_VAL := --pretrain-iterations $(AG_PRETRAIN) --disc-noise 0.3
ours-nocls_VAL := --pretrain-iterations $(AG_PRETRAIN) --no-classifier
ours-dlr1e-5_VAL := --pretrain-iterations $(AG_PRETRAIN) --disc-lr 1e-5
ours-nocls-dlr1e-5_VAL := --pretrain-iterations $(AG_PRETRAIN) --no-classifier --disc-lr 1e-5
ours-critic_VAL := --pretrain-iterations $(AG_PRETRAIN) $(AG_CRITIC)
ours-critic-normal_VAL := --pretrain-iterations $(AG_PRETRAIN) $(AG_CRITIC) --start normal
pose_VAL := --pretrain-iterations 0 --generator pose
pose-critic_VAL := --pretrain-iterations 0 --generator pose $(AG_CRITIC)
ours_VAL_LABEL := ours (paper defaults: sigma1 0.05, the decoder learns on)
ours-frozen_VAL_LABEL := decoder fixed (--freeze-decoder, the authors' code)
ours-frozen-s1.6_VAL_LABEL := decoder fixed, sigma1 1.6 (0.05 summed over our batch of 32)
ours-s6.4_VAL_LABEL := sigma1 6.4 (the authors' code: 0.1 summed over their batch of 64)
ours-frozen-s6.4_VAL_LABEL := decoder fixed, sigma1 6.4
ours-small_VAL_LABEL := generator steps start small (--step-init small)
ours-small-s6.4_VAL_LABEL := steps start small, sigma1 6.4
ours-lr2e-5_VAL_LABEL := the GAN's learning rate 2e-5 (--lr 2e-5)
ours-small-lr2e-5_VAL_LABEL := steps start small, the GAN's learning rate 2e-5 (--lr 2e-5)
ours-dmotion_VAL_LABEL := discriminator sees frames and their differences (--disc-input motion)
ours-dmotion-lr2e-5_VAL_LABEL := discriminator sees frames and their differences, learning rate 2e-5
ours-dall_VAL_LABEL := discriminator reads every step (--disc-pool all)
ours-dauthors_VAL_LABEL := the authors' discriminator (--disc-input motion --disc-pool all)
ours-dauthors-lr2e-5_VAL_LABEL := the authors' discriminator, learning rate 2e-5
ours-noise0.1_VAL_LABEL := instance noise 0.1 on what the discriminator sees (--disc-noise 0.1)
ours-noise0.3_VAL_LABEL := instance noise 0.3 (--disc-noise 0.3)
ours-nocls_VAL_LABEL := no classifier and no cycle loss (--no-classifier)
ours-dlr1e-5_VAL_LABEL := the discriminator 10x slower than the generator (--disc-lr 1e-5)
ours-nocls-dlr1e-5_VAL_LABEL := no classifier, the discriminator 10x slower
ours-critic_VAL_LABEL := a Wasserstein critic of whole clips with gradient penalty, 5 critic steps per iteration (--discriminator critic --d-steps 5)
ours-critic-normal_VAL_LABEL := the critic, each sequence's latent starting at h_1 ~ N(0, I), the decoder's pre-training distribution (--start normal)
pose_VAL_LABEL := $(AG_LABEL_pose)
pose-critic_VAL_LABEL := direct-pose RNN baseline against the same critic (--discriminator critic --d-steps 5)
# $(call ag_val_from,MODEL): its pre-training iterations (the GAN's rows come after them)
ag_val_from = $(if $(filter pose%,$(1)),0,$(AG_PRETRAIN))
# Every candidate is an option set on top of the paper's form (--paper-form: these runs chose the
# defaults, so they do not start from them)
ag_val_train = --paper-form $($(2)_VAL) --iterations $(AG_VAL_ITERATIONS) $(AG_OPTIONS) --validation-subjects $($(1)_VAL_SUBJECTS)

.PHONY: actgan-validation
actgan-validation: $(foreach s,$(AG_SETS),$(AG)/$(s)/validation.md $(AG)/$(s)/validation.png)
	@for s in $(AG_SETS); do echo; cat $(AG)/$$s/validation.md; echo "curves: $(AG)/$$s/validation.png"; done

define AG_VAL_RULES
$(AG)/%/validate/$(1).args: FORCE
	@mkdir -p $$(@D)
	@echo '$$(call ag_val_train,$$*,$(1))' $$(write_if_changed)
$(AG)/%/validate/$(1).h5: $(AG)/%/data.h5 $(AG)/%/validate/$(1).args
	$$(call launch,train) $$(BIN)/train-actgan -f --threads $$(TRAIN_THREADS) --print-every 100 --checkpoint-every 200 --resume \
	  $$(call ag_val_train,$$*,$(1)) $$< -o $$@ 2>&1 | tee $$(@:.h5=.log)
# The size of its poses at the first and the last frame (20 sequences per class, scripts/pose-norms).
$(AG)/%/validate/$(1).norms: $(AG)/%/validate/$(1).h5
	$$(call launch,generate) $$(BIN)/gen-actgan -q -f --count 20 --seed 3 $$< -o $$(@:.norms=.sample.h5)
	$$(DF_ROOT)/scripts/pose-norms $$(@:.norms=.sample.h5) > $$@.tmp && mv $$@.tmp $$@
endef
$(foreach v,$(AG_VAL_MODELS),$(eval $(call AG_VAL_RULES,$(v))))
$(AG)/%/validate/real.mmd.json: $(AG)/%/data.h5
	@mkdir -p $(@D)
	$(call launch,eval) $(BIN)/eval-metrics -q -f $< $< --pred-subjects $($*_VAL_REF_SUBJECTS) \
	  --truth-subjects $($*_VAL_SUBJECTS) --json $@.tmp > /dev/null && mv $@.tmp $@
$(AG)/%/data.norms: $(AG)/%/data.h5
	$(DF_ROOT)/scripts/pose-norms $< > $@.tmp && mv $@.tmp $@
# A model's log rows: iteration loss disc adv smooth cycle gp val_mmd_avg val_mmd_seq
# val_mmd_motion_avg val_mmd_motion_seq (columns 8-11)
$(AG)/%.val.txt: $(AG)/%.h5
	$(call h5_values,$<,/training/log,%.6g) | tr -c '0-9.e+\n-' ' ' | xargs -n 11 > $@
# min (at iteration) of column $(2) over the GAN's rows (iteration > pre-training), and the last
ag_val_min = awk -v from=$(3) '$$1 > from { if (!n++ || $$$(2) < m) { m = $$$(2); at = $$1 } last = $$$(2) } \
  END { printf "%.4f (%d) | %.4f", m, at - from, last }' $(1)
# $(call ag_val_at_pretrain,STEM,COLUMN): ours' value at the end of pre-training
ag_val_at_pretrain = awk '$$1 == $(AG_PRETRAIN) { printf "%.4f", $$$(2) }' $(AG)/$(1)/validate/ours.val.txt
ag_real = $(call ag_mmd,$(AG)/$(1)/validate/real.mmd.json,$(2))
$(AG)/%/validation.md: $(foreach v,$(AG_VAL_MODELS),$(AG)/%/validate/$(v).val.txt $(AG)/%/validate/$(v).norms) $(AG)/%/data.norms \
    $(AG)/%/validate/real.mmd.json
	{ echo "**$*** — the GAN's iteration count on a validation part (training subjects $($*_VAL_SUBJECTS) held out; $(AG_VAL_ITERATIONS) GAN iterations; 100 sequences per class). Each MMD: the minimum over the GAN's iterations (at GAN iteration) / the last. Motion: the same measures of frame differences x_t+1 - x_t (eval-metrics)."; echo; \
	  echo "| model | MMD_avg min (at) | last | MMD_seq min (at) | last | motion MMD_avg min (at) | last | motion MMD_seq min (at) | last | pose norm, frame 1 -> last |"; \
	  echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"; \
	  echo "| the real clips of training subjects $($*_VAL_REF_SUBJECTS) (the data's own level: a generator that reproduced them exactly) | $$($(call ag_real,$*,avg)) | | $$($(call ag_real,$*,seq)) | | $$($(call ag_real,$*,motion_avg)) | | $$($(call ag_real,$*,motion_seq)) | | |"; \
	  echo "| ours at the end of pre-training (GAN iteration 0: decoder trained, LSTM not) | $$($(call ag_val_at_pretrain,$*,8)) | | $$($(call ag_val_at_pretrain,$*,9)) | | $$($(call ag_val_at_pretrain,$*,10)) | | $$($(call ag_val_at_pretrain,$*,11)) | | |"; \
	  $(foreach v,$(AG_VAL_MODELS),echo "| $($(v)_VAL_LABEL) | $(foreach c,8 9 10 11,$$($(call ag_val_min,$(AG)/$*/validate/$(v).val.txt,$(c),$(call ag_val_from,$(v)))) |) $$(awk '{ printf "%s -> %s", $$1, $$2 }' $(AG)/$*/validate/$(v).norms) |";) \
	  echo; echo "Pose norm: the mean Euclidean norm of a pose (z-scored coordinates) at the first and the last frame; the real clips (data.h5): $$(awk '{ printf "%s -> %s", $$1, $$2 }' $(AG)/$*/data.norms)."; \
	} $(write_if_changed)
# $(call ag_val_panel,STEM,COLUMN,TITLE,REFERENCE): one panel of validation.png (the direct-pose
# baselines, pose*, have no pre-training: their GAN iterations start at 0)
ag_val_panel = set title '$(1): $(3)' noenhanced; \
  plot for [v in files] '$(AG)/$(1)/validate/'.v.'.val.txt' using (\$$1-$(AG_PRETRAIN)):(\$$1 >= $(AG_PRETRAIN) ? \$$$(2) : 1/0) with linespoints title v, \
       for [v in pose_files] '$(AG)/$(1)/validate/'.v.'.val.txt' using 1:$(2) with linespoints title v.' (direct pose)', \
       $(4) with lines lw 3 lc rgb 'black' title 'real clips of subjects $($(1)_VAL_REF_SUBJECTS)';
$(AG)/%/validation.png: $(foreach v,$(AG_VAL_MODELS),$(AG)/%/validate/$(v).val.txt) $(AG)/%/validate/real.mmd.json
	gnuplot -e "ref_avg = $$($(call ag_real,$*,avg)); ref_seq = $$($(call ag_real,$*,seq)); \
	  ref_motion_avg = $$($(call ag_real,$*,motion_avg)); ref_motion_seq = $$($(call ag_real,$*,motion_seq)); \
	  set terminal pngcairo size 1000,1600; set output '$@'; set multiplot layout 4,1; \
	  set key outside right noenhanced font ',8' spacing 0.75; set lmargin at screen 0.08; set rmargin at screen 0.72; \
	  set xrange [0:*]; set logscale y; set ylabel 'MMD_u^2'; set xlabel 'GAN iteration'; \
	  files = '$(filter-out pose%,$(AG_VAL_MODELS))'; pose_files = '$(filter pose%,$(AG_VAL_MODELS))'; \
	  set yrange [0.2:3]; set ytics (0.2, 0.3, 0.5, 0.7, 1, 1.5, 2, 3); \
	  $(call ag_val_panel,$*,8,MMD_avg against held-out training subjects $($*_VAL_SUBJECTS) (GAN iteration 0: end of pre-training),ref_avg) \
	  $(call ag_val_panel,$*,9,MMD_seq,ref_seq) \
	  set yrange [0.001:3]; set ytics (0.001, 0.003, 0.01, 0.03, 0.1, 0.3, 1, 3); \
	  $(call ag_val_panel,$*,10,motion MMD_avg (frame differences),ref_motion_avg) \
	  $(call ag_val_panel,$*,11,motion MMD_seq,ref_motion_seq) unset multiplot"
