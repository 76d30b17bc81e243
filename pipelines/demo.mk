# The demo: what `make demo` runs. Synthetic data only (no downloads).
DEMO := $(OUT)/demo

.PHONY: demo
demo: $(DEMO)/finger.h5 $(DEMO)/bumps.h5 $(DEMO)/flag/0000.obj
	@echo
	@echo "== h5check: file kinds, shapes, compression, history"
	$(BIN)/h5check $(DEMO)/finger.h5 $(DEMO)/bumps.h5
	@echo
	@echo "== outputs"
	@echo "  $(DEMO)/finger.h5   finger bending and twisting 400 deg (acap kind, positions)"
	@echo "  $(DEMO)/bumps.h5    surface with planted coarse/fine deformations + ground truth"
	@echo "  $(DEMO)/flag/       waving flag as OBJ files (open them in any mesh viewer)"
	@echo "  h5dump reads them with: HDF5_PLUGIN_PATH=$(HDF5_PLUGIN_PATH) h5dump -H -p FILE"

$(DEMO):
	mkdir -p $@

$(DEMO)/finger.h5: | $(DEMO)
	$(BIN)/synth-meshseq --kind finger --twist 400 --frames 120 --resolution 16 -f -o $@

$(DEMO)/bumps.h5: | $(DEMO)
	$(BIN)/synth-meshseq --kind bumps --frames 200 --resolution 40 --seed 1 -f -o $@

$(DEMO)/flag/0000.obj: | $(DEMO)
	$(BIN)/synth-meshseq --kind flag --frames 60 --resolution 20 -f -o $(DEMO)/flag
