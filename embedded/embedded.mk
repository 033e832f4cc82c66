# `make embedded` (the top-level Makefile runs this file with -j2 and LIBS, the folders of
# generated/): every library cross-compiled for a Cortex-M4F in double and with
# CODEGEN_FLOAT, linked into the test firmware (embedded/: start-up, linker script, and a
# main written from the library's API spec by tests/support/c/make_driver.py --firmware), run under
# QEMU's mps2-an386 and compared with the same main built for the host; embedded/report.py
# then writes $(REPORT).md and .json (sizes, stack, instructions, the comparison).
PYTHON   ?= python3
OUT      ?= build/embedded
REPORT   ?= embedded/report
BUILDS    = double float
double_DEFINES =
float_DEFINES  = -DCODEGEN_FLOAT

ARM_CC    = arm-none-eabi-gcc
CPU       = -mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16
# -fstack-usage and -fcallgraph-info=su leave NAME.su and NAME.ci beside each object: the
# frames and the call graph embedded/report.py walks for the worst-case stack.
# runtime/cflags.txt's sets: base is -std=c99 -ffp-contract=off, which keeps the M4's
# single-precision fused multiply-add out of the float build (gcc's default in ISO C mode;
# said, since the host comparison rests on it); optimize is -O2.
include runtime/cflags.txt
ARM_CFLAGS = $(CPU) $(optimize) $(base) -Wall -Wextra -ffunction-sections \
             -fdata-sections -fstack-usage -fcallgraph-info=su
# No --gc-sections: every function of the library stays, and with it every C library
# function it calls, whose frames the stack report reads from the firmware.
ARM_LDFLAGS = $(CPU) -T embedded/mps2_an386.ld -nostartfiles --specs=rdimon.specs
# The host reference: IEEE double as written (no contraction into fma; x86-64 has no excess
# precision), so that every value can be compared bit for bit. -O0: the arithmetic is the
# same at any level, and the largest library compiles in a second instead of half a minute.
HOST_CFLAGS = $(base) -O0 -Wall -Wextra

# Virtual time per instruction is 2^ICOUNT_SHIFT ns: 64 ns, longer than the 40 ns tick of the
# board's 25 MHz timer, so the count read from it is exact (platform_qemu.c).
ICOUNT_SHIFT = 6
QEMU = qemu-system-arm -M mps2-an386 -nographic -monitor none -serial none \
       -semihosting-config enable=on,target=native -icount shift=$(ICOUNT_SHIFT)

RUNTIME  = $(basename $(notdir $(wildcard generated/runtime/*.c)))
FIRMWARE = startup platform_qemu

.PHONY: all
.DELETE_ON_ERROR:
all: $(REPORT).md

# $(1): a build (double or float)
define build_rules
$(OUT)/$(1)/runtime/%.o: generated/runtime/%.c $(wildcard generated/runtime/*.h)
	@mkdir -p $$(@D)
	$(ARM_CC) $(ARM_CFLAGS) $($(1)_DEFINES) -Igenerated/runtime -c $$< -o $$@
$(OUT)/$(1)/firmware/%.o: embedded/%.c embedded/platform.h
	@mkdir -p $$(@D)
	$(ARM_CC) $(ARM_CFLAGS) $($(1)_DEFINES) -DICOUNT_SHIFT=$(ICOUNT_SHIFT) -Iembedded -c $$< -o $$@
endef

# $(1): a build, $(2): a library
define library_rules
$(OUT)/$(1)/$(2)/%.o: generated/$(2)/%.c $(wildcard generated/$(2)/*.h generated/runtime/*.h)
	@mkdir -p $$(@D)
	$(ARM_CC) $(ARM_CFLAGS) $($(1)_DEFINES) -Igenerated/$(2) -Igenerated/runtime -c $$< -o $$@
$(OUT)/$(1)/$(2)/main.o: $(OUT)/main_$(2).c embedded/platform.h \
    $(wildcard generated/$(2)/*.h generated/runtime/*.h)
	@mkdir -p $$(@D)
	$(ARM_CC) $(ARM_CFLAGS) $($(1)_DEFINES) -Iembedded -Igenerated/$(2) -Igenerated/runtime \
	  -c $$< -o $$@
$(OUT)/$(1)/$(2)/firmware.elf: $(OUT)/$(1)/$(2)/main.o \
    $(patsubst generated/$(2)/%.c,$(OUT)/$(1)/$(2)/%.o,$(wildcard generated/$(2)/*.c)) \
    $(RUNTIME:%=$(OUT)/$(1)/runtime/%.o) $(FIRMWARE:%=$(OUT)/$(1)/firmware/%.o) \
    embedded/mps2_an386.ld
	$(ARM_CC) $(ARM_LDFLAGS) -Wl,-Map=$$(@:.elf=.map) $$(filter %.o,$$^) -lm -o $$@
$(OUT)/$(1)/$(2)/target.txt: $(OUT)/$(1)/$(2)/firmware.elf
	timeout 600 $(QEMU) -kernel $$< > $$@
$(OUT)/$(1)/$(2)/host.txt: $(OUT)/main_$(2).c embedded/platform_host.c \
    $(wildcard generated/$(2)/*.[ch] generated/runtime/*.[ch])
	@mkdir -p $$(@D)
	$(CC) $(HOST_CFLAGS) $($(1)_DEFINES) -Iembedded -Igenerated/$(2) -Igenerated/runtime \
	  $(OUT)/main_$(2).c embedded/platform_host.c generated/$(2)/*.c generated/runtime/*.c \
	  -lm -o $(OUT)/$(1)/$(2)/host
	$(OUT)/$(1)/$(2)/host > $$@
endef

# $(1): a library; its firmware main serves every build
define main_rule
$(OUT)/main_$(1).c: generated/$(1)/$(1)_api.json tests/support/c/make_driver.py
	@mkdir -p $$(@D)
	$(PYTHON) tests/support/c/make_driver.py --firmware generated/$(1) $$@
endef

$(foreach lib,$(LIBS),$(eval $(call main_rule,$(lib))))
$(foreach build,$(BUILDS),$(eval $(call build_rules,$(build))))
$(foreach build,$(BUILDS),$(foreach lib,$(LIBS),$(eval $(call library_rules,$(build),$(lib)))))

# A library's builds side by side: with -j2 the largest library's compiles run together.
OUTPUTS = $(foreach lib,$(LIBS),$(foreach build,$(BUILDS),$(OUT)/$(build)/$(lib)/target.txt \
                                                          $(OUT)/$(build)/$(lib)/host.txt))
$(REPORT).md: $(OUTPUTS) $(wildcard embedded/*.py)
	$(PYTHON) embedded/report.py $(OUT) $(REPORT) "$(ARM_CFLAGS)"
