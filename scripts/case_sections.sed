# Issue 18: case_type made of sections. Renames every flat case component to its section path.
# Apply with: sed -E -i -f scripts/case_sections.sed FILE...
# Matches the variable `case` (also `sim%case%...`), not `local_case%...`; other names of a
# case_type variable (mpm_decomposition's `local`, tests' `other`, `slab(k)`) are renamed by hand.
# domain
s/\bcase%ncells\b/case%domain%ncells/g
s/\bcase%dx\b/case%domain%dx/g
s/\bcase%origin\b/case%domain%origin/g
s/\bcase%bc_friction\b/case%domain%bc_friction/g
s/\bcase%bc\b/case%domain%bc/g
# particles
s/\bcase%ppc\b/case%particles%ppc/g
s/\bcase%distribution\b/case%particles%distribution/g
s/\bcase%seed\b/case%particles%seed/g
# solver
s/\bcase%scheme\b/case%solver%scheme/g
s/\bcase%shape\b/case%solver%shape/g
s/\bcase%apic\b/case%solver%apic/g
s/\bcase%flip_fraction\b/case%solver%flip_fraction/g
s/\bcase%fbar\b/case%solver%fbar/g
# time
s/\bcase%dt\b/case%time%dt/g
s/\bcase%cfl\b/case%time%cfl/g
s/\bcase%allow_unstable\b/case%time%allow_unstable/g
s/\bcase%tend\b/case%time%tend/g
# damping
s/\bcase%damping_value\b/case%damping%value/g
s/\bcase%damping\b([^%]|$)/case%damping%type\1/g
# contact
s/\bcase%contact_type\b/case%contact%type/g
s/\bcase%contact_mu\b/case%contact%mu/g
s/\bcase%contact_file\b/case%contact%file/g
s/\bcase%contact_scale\b/case%contact%scale/g
s/\bcase%contact_offset\b/case%contact%offset/g
# output
s/\bcase%output_interval\b/case%output%interval/g
s/\bcase%output_dir\b/case%output%directory/g
s/\bcase%output_fields\b/case%output%fields/g
s/\bcase%output_grid\b/case%output%grid/g
s/\bcase%overwrite\b/case%output%overwrite/g
s/\bcase%history_interval\b/case%output%history_interval/g
# progress
s/\bcase%progress_seconds\b/case%progress%interval/g
# checkpoint
s/\bcase%checkpoint_steps\b/case%checkpoint%every_steps/g
s/\bcase%checkpoint_minutes\b/case%checkpoint%every_minutes/g
s/\bcase%checkpoint_file\b/case%checkpoint%file/g
s/\bcase%checkpoint_on_signal\b/case%checkpoint%on_signal/g
# guard
s/\bcase%guard_energy_factor\b/case%guard%energy_factor/g
s/\bcase%guard_snapshot_steps\b/case%guard%snapshot_steps/g
