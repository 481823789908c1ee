# The Makefile's variables that a user sets (make ... NAME=VALUE), checked once
# as numbers or names: a clear error naming the variable, the value and what is
# allowed, never a silent reinterpretation (MEMBERS=010 read as octal, a PRESET
# that is a path out of results/, a count that makes make -n run for ever).

# $(call sh_word,TEXT): TEXT as one single-quoted shell word
sh_word = '$(subst ','\'',$(1))'

# $(call check_count,NAME,MIN,MAX): $(NAME) must be a decimal whole number from MIN to MAX
# (digits only: no sign, no leading zero, no spaces)
# (the case patterns open with a parenthesis too: make counts them; 10 digits or more are refused
# before the shell compares them as numbers)
check_count = $(if $(shell v=$(call sh_word,$($(1))); case "$$v" in (''|0?*|*[!0-9]*|??????????*) ;; \
  (*) [ "$$v" -ge $(2) ] && [ "$$v" -le $(3) ] && echo ok;; esac),,\
  $(error $(1)=$($(1)): must be a whole number from $(2) to $(3), in decimal digits without a leading zero))

# $(call check_name,NAME,ALLOWED...): $(NAME) must be one of the words ALLOWED, with no space after it (it
# becomes part of paths: PRESET='fast ' made results/fast a target of its own); a % is refused before filter,
# which would read it as a pattern matching every word
check_name = $(if $(and $(filter 1,$(words $($(1)))),$(if $(subst $(strip $($(1))),,$($(1))),,ok),\
  $(if $(findstring %,$($(1))),,$(filter $($(1)),$(2)))),,\
  $(error $(1)=$($(1)): must be one of: $(strip $(2))))

PRESET_NAMES := quick $(sort $(basename $(notdir $(wildcard pipeline/presets/*.toml))))
INTRUDER_NAMES := $(sort $(basename $(notdir $(wildcard pipeline/intruders/*.toml))))

# what the generated stage rules write for a comma and parentheses inside $(call ...) (pipeline/stages.py)
comma := ,
lparen := (
rparen := )
