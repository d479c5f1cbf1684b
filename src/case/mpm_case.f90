!> The resolved description of a simulation case, and the case-file reader interface.
!>
!> `case_type` holds every setting of a run with every default resolved and every value
!> checked; the rest of the code reads settings only from it. It is made of one section type
!> per key of the case file (`case%domain%dx`, `case%time%tend`), each declared, read and
!> checked in its own module `mpm_case_<section>` through a `cursor_type` (mpm_case_cursor).
!> The reader of the whole file lives in the submodule `mpm_case_reader`, the --check text in
!> `mpm_case_summary`. The case layer uses no model, solver or output module; a material is
!> read and checked by its constitutive law (src/material/, mpm_material_registry).
module mpm_case
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_case_domain, only: domain_section_type
    use mpm_case_particles, only: particles_section_type, dist_regular, dist_random, &
        distribution_names
    use mpm_case_materials, only: material_spec_type
    use mpm_case_bodies, only: body_spec_type
    use mpm_case_solver, only: solver_section_type, scheme_usf, scheme_usl, scheme_musl, &
        scheme_names
    use mpm_case_time, only: time_section_type
    use mpm_case_damping, only: damping_section_type, damping_none, damping_local, &
        damping_kinetic, damping_names
    use mpm_case_initial_stress, only: initial_stress_section_type, initial_none, initial_k0
    use mpm_case_contact, only: contact_section_type
    use mpm_case_output, only: output_section_type
    use mpm_case_progress, only: progress_section_type
    use mpm_case_checkpoint, only: checkpoint_section_type
    use mpm_case_guard, only: guard_section_type
    use mpm_case_pore_water, only: pore_water_section_type
    use mpm_case_loads, only: load_spec_type
    use mpm_time_function, only: time_function_type
    use mpm_case_motion, only: motion_spec_type
    use mpm_case_strength_reduction, only: strength_reduction_section_type
    implicit none
    private
    public :: case_type, read_case_file, read_case_string, case_summary, case_key_paths
    ! the section types and their enumerations, for the users of the case
    public :: domain_section_type, particles_section_type, material_spec_type, body_spec_type
    public :: solver_section_type, time_section_type, damping_section_type
    public :: contact_section_type, output_section_type, progress_section_type
    public :: checkpoint_section_type, guard_section_type, initial_stress_section_type
    public :: initial_none, initial_k0, load_spec_type, time_function_type, motion_spec_type
    public :: scheme_usf, scheme_usl, scheme_musl, scheme_names
    public :: damping_none, damping_local, damping_kinetic, damping_names
    public :: dist_regular, dist_random, distribution_names

    !> Every setting of a run, resolved and checked: the top-level keys of the case file and
    !> one section per object key, in the order of docs/input.md.
    type :: case_type
        character(len=:), allocatable :: file
            !! case file path as given ("<string>" for cases read from text)
        character(len=:), allocatable :: name
            !! case name (default: file name without directory and extension)
        integer :: dim = 2
            !! number of space dimensions (2: plane strain, 3)
        type(domain_section_type) :: domain
            !! `domain`: the grid and its boundary conditions
        type(particles_section_type) :: particles
            !! `particles`: particles per cell and their placement
        type(material_spec_type), allocatable :: materials(:)
            !! `materials`, in file order
        type(body_spec_type), allocatable :: bodies(:)
            !! `bodies`, in file order
        real(wp) :: gravity(3) = 0.0_wp
            !! gravitational acceleration [m/s2]
        type(pore_water_section_type) :: pore_water
            !! `pore_water`: the saturated soils, their water, its initial level and drainage
        type(solver_section_type) :: solver
            !! `solver`: update scheme, shape function, transfer
        type(time_section_type) :: time
            !! `time`: end time and time step
        type(damping_section_type) :: damping
            !! `damping`
        type(initial_stress_section_type) :: initial_stress
            !! `initial_stress`
        type(load_spec_type), allocatable :: loads(:)
            !! `loads`, in file order (none when absent)
        type(motion_spec_type), allocatable :: motions(:)
            !! `prescribed_motion`, in file order (none when absent)
        type(strength_reduction_section_type) :: strength_reduction
            !! `strength_reduction`: a factor-of-safety analysis instead of one run
        type(contact_section_type) :: contact
            !! `contact`: the rigid terrain surface
        type(output_section_type) :: output
            !! `output`: folder, intervals and fields
        type(progress_section_type) :: progress
            !! `progress`: the progress lines
        character(len=:), allocatable :: save_state
            !! state file to write at the end ("" for none)
        character(len=:), allocatable :: load_state
            !! state file to start from ("" for none)
        type(checkpoint_section_type) :: checkpoint
            !! `checkpoint`: when and where checkpoints are written
        type(guard_section_type) :: guard
            !! `guard`: the blow-up guard
        character(len=:), allocatable :: text
            !! JSON text of the case file as read (checkpoints keep it); "" from text
    end type case_type

    interface
        !> Read, check and resolve a case file.
        module subroutine read_case_file(path, case, error)
            character(len=*), intent(in) :: path
                !! case file (JSON)
            type(case_type), intent(out) :: case
                !! resolved case
            type(error_type), allocatable, intent(out) :: error
                !! set (code exit_input) on any invalid input
        end subroutine read_case_file

        !> Read, check and resolve a case given as JSON text (tests, tools).
        module subroutine read_case_string(text, case, error, source)
            character(len=*), intent(in) :: text
                !! JSON text of the case
            type(case_type), intent(out) :: case
                !! resolved case
            type(error_type), allocatable, intent(out) :: error
                !! set (code exit_input) on any invalid input
            character(len=*), intent(in), optional :: source
                !! name used for the case in messages and as default case name
        end subroutine read_case_string

        !> A multi-line, human-readable summary of the resolved case (for --check and logs).
        module function case_summary(case) result(text)
            type(case_type), intent(in) :: case
                !! resolved case
            character(len=:), allocatable :: text
                !! summary, lines separated by new_line("a")
        end function case_summary

        !> Every key path the case reader accepts, from the reader's own key lists (the schema
        !> test compares them with docs/case.schema.json). An object's keys are written
        !> "section.key", an array item's "array[].key", and a material's, which depend on its
        !> type, "materials[type=NAME].key" for each type name (aliases included):
        !> "domain.boundaries.xmin.mu", "bodies[].file", "materials[type=drucker_prager].cone".
        !> (A subroutine: gfortran 12 fails on a deferred-length array function result here.)
        module subroutine case_key_paths(paths)
            character(len=:), allocatable, intent(out) :: paths(:)
                !! key paths, in the reader's order, blank-padded to the longest
        end subroutine case_key_paths
    end interface

end module mpm_case
