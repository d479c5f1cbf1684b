!> Save and load the particle state of a run (restart files), as HDF5.
!>
!> A state file holds every saved array of the particle field table (mpm_particles, in its
!> order) exactly as stored (no padding), the time and step, and what is needed to check
!> that it fits the case it is loaded into: the grid (dimension, ncells, dx, origin) and the
!> material names. Material indices are stored as in the saving case and remapped by name
!> when loading, so a case may list its materials in another order or add new ones. The
!> layout is described in docs/output.md.
!>
!> A checkpoint is a state file with a group "run" more (run_record_type): what the time
!> loop needs to continue exactly where it stopped (energies, the running contact loads, the
!> output schedule and the outputs written, the case file's text). Any reader of state files
!> reads a checkpoint as a state.
module mpm_state
    use mpm_kinds, only: wp, i8
    use mpm_strings, only: int_text, real_text, reals_text
    use mpm_error, only: error_type, fatal_error, exit_other, exit_input
    use mpm_case, only: case_type
    use mpm_particles, only: particles_type, new_particles, nstress_of, particle_field_type, &
        particle_field_count, particle_field, values_per_particle, field_units, field_held, &
        get_field, get_field_integers, put_field, put_field_integers, hold_field, per_particle, &
        per_tensor, held_always
    use mpm_hdf5, only: hdf5_location_type, text_type, hdf5_initialize, hdf5_is_hdf5_file, &
        hdf5_create_file, hdf5_open_file, hdf5_create_group, hdf5_open_group, hdf5_close, &
        hdf5_close_after, hdf5_has_attribute, hdf5_has_link, hdf5_write_dataset, &
        hdf5_read_dataset, hdf5_write_attribute, hdf5_read_attribute
    use mpm_filesystem, only: make_directory, directory_exists, file_exists, rename_file, &
        remove_file, parent_directory
    use mpm_version, only: mpm_version_string
    implicit none
    private
    public :: save_state, load_state, read_run_record, run_record_type, state_particle_count
    public :: state_format, state_format_version, state_energy_terms

    character(len=*), parameter :: state_format = "mpm-geo-state"
        !! value of the root attribute "format" of a state file
    integer, parameter :: state_format_version = 1
        !! layout version written by this build (and the only one it reads)
    integer, parameter :: state_energy_terms = 16
        !! values of the `energy` attribute of a run record (mpm_solver energy_record); the
        !! run records of builds before the energy balance held 4 and no `energy_terms`
    real(wp), parameter :: grid_rtol = 1.0e-12_wp
        !! relative tolerance when comparing dx and origin with the case's [-]

    !> What a checkpoint keeps besides the particles: how the run goes on, bit for bit.
    type :: run_record_type
        character(len=:), allocatable :: case_file
            !! case file the run was started with (as given on its command line)
        character(len=:), allocatable :: case_text
            !! the JSON text of that case file
        character(len=:), allocatable :: output_dir
            !! output folder of the run
        integer :: images = 1
            !! images (processes) of the run
        real(wp) :: dt = 0.0_wp
            !! time step of the last step [s]
        real(wp) :: energy(state_energy_terms) = 0.0_wp
            !! the energy terms of the run (mpm_solver energy_record) [J]
        real(wp) :: kinetic_previous = 0.0_wp
            !! kinetic energy of the step before (kinetic damping) [J]
        real(wp) :: next_output = 0.0_wp
            !! time of the next particle output [s]
        real(wp) :: next_history = 0.0_wp
            !! time of the next line of the energy history [s]
        real(wp) :: wall = 0.0_wp
            !! wall-clock time of the run's time loop so far [s]
        real(wp), allocatable :: output_time(:)
            !! time of each output written (outputs) [s]
        integer, allocatable :: output_step(:)
            !! step of each output written (outputs)
        integer, allocatable :: output_counts(:, :)
            !! particles in each image's file of each output (images, outputs)
        logical, allocatable :: output_id(:)
            !! the files of each output hold particle ids (outputs)
        real(wp), allocatable :: face_load(:)
            !! running normal load of every frictional face node of the whole grid [N s]
        integer(i8), allocatable :: terrain_node(:)
            !! node of the whole grid (1-based linear index) of every terrain contact pair,
            !! ascending
        real(wp), allocatable :: terrain_load(:)
            !! running normal load of each terrain contact pair of terrain_node [N s]
        integer, allocatable :: scatter_order(:)
            !! a one-pass run: the particle order of the P2G its last step did for the next one
            !! (the restart does that P2G again in that order: the same sums)
        real(wp), allocatable :: acting_disp(:)
            !! a run with Kelvin-Voigt faces: the displacement of every (node, acting face)
            !! pair of the grid, dim per pair, in the grid's order (one image) [m]
    end type run_record_type

contains

    !> Write the particle state to `path` (through `path.tmp` and a rename: never half a file).
    subroutine save_state(path, case, particles, time, step, error, run)
        character(len=*), intent(in) :: path
            !! state file to write; its folder is created when missing
        type(case_type), intent(in) :: case
            !! the case of the run (grid and materials are recorded for checks at load)
        type(particles_type), intent(in) :: particles
            !! particles to save
        real(wp), intent(in) :: time
            !! simulated time [s]
        integer, intent(in) :: step
            !! time step number
        type(error_type), allocatable, intent(out) :: error
            !! set when the file cannot be written (the message names it)
        type(run_record_type), intent(in), optional :: run
            !! makes the state a checkpoint: how the run goes on

        character(len=:), allocatable :: folder, temporary
        type(error_type), allocatable :: ignored

        if (particles%dim /= case%dim) then
            call fatal_error(error, "cannot save the state '"//path//"': the particles have "// &
                "dimension "//int_text(particles%dim)//" but the case has "// &
                int_text(case%dim), exit_other)
            return
        end if
        folder = parent_directory(path)
        if (len(folder) > 0) then
            if (.not. directory_exists(folder)) then
                call make_directory(folder, error)
                if (allocated(error)) return
            end if
        end if
        call hdf5_initialize(error)
        if (allocated(error)) return

        temporary = path//".tmp"
        call write_state_file(temporary, case, particles, time, step, error, run, path)
        if (allocated(error)) then
            ! (a checkpoint of that name from before stays whole)
            call remove_file(temporary, ignored)
            return
        end if
        call rename_file(temporary, path, error)
    end subroutine save_state

    subroutine write_state_file(path, case, particles, time, step, error, run, shown_as)
        character(len=*), intent(in) :: path
        type(case_type), intent(in) :: case
        type(particles_type), intent(in) :: particles
        real(wp), intent(in) :: time
        integer, intent(in) :: step
        type(error_type), allocatable, intent(out) :: error
        type(run_record_type), intent(in), optional :: run
        character(len=*), intent(in) :: shown_as
            !! the name messages give the file (the final name of the .tmp)

        type(hdf5_location_type) :: file, group
        character(len=:), allocatable :: case_name

        case_name = ""
        if (allocated(case%name)) case_name = case%name
        call hdf5_create_file(path, file, error, shown_as)
        if (allocated(error)) return
        steps: block
            call hdf5_write_attribute(file, "format", state_format, error)
            if (allocated(error)) exit steps
            call hdf5_write_attribute(file, "format_version", state_format_version, error)
            if (allocated(error)) exit steps
            call hdf5_write_attribute(file, "mpm_geo_version", mpm_version_string, error)
            if (allocated(error)) exit steps
            call hdf5_write_attribute(file, "case_name", case_name, error)
            if (allocated(error)) exit steps
            call hdf5_write_attribute(file, "dimension", case%dim, error)
            if (allocated(error)) exit steps
            call hdf5_write_attribute(file, "ncells", case%domain%ncells, error)
            if (allocated(error)) exit steps
            call hdf5_write_attribute(file, "dx", case%domain%dx, error)
            if (allocated(error)) exit steps
            call hdf5_write_attribute(file, "origin", case%domain%origin, error)
            if (allocated(error)) exit steps
            call hdf5_write_attribute(file, "n", particles%n, error)
            if (allocated(error)) exit steps
            call hdf5_write_attribute(file, "nstress", particles%nstress, error)
            if (allocated(error)) exit steps
            call hdf5_write_attribute(file, "nstate", particles%nstate, error)
            if (allocated(error)) exit steps
            call hdf5_write_attribute(file, "time", time, error)
            if (allocated(error)) exit steps
            call hdf5_write_attribute(file, "step", step, error)
            if (allocated(error)) exit steps
            call hdf5_write_attribute(file, "materials", material_names(case), error)
            if (allocated(error)) exit steps
            call hdf5_write_attribute(file, "material_types", material_types(case), error)
            if (allocated(error)) exit steps

            call hdf5_create_group(file, "particles", group, error)
            if (allocated(error)) exit steps
            call write_particles(group, particles, error)
            call hdf5_close_after(group, error)
            if (allocated(error) .or. .not. present(run)) exit steps
            call hdf5_create_group(file, "run", group, error)
            if (allocated(error)) exit steps
            call write_run_record(group, run, error)
            call hdf5_close_after(group, error)
        end block steps
        call hdf5_close_after(file, error)
    end subroutine write_state_file

    !> Every saved array of the field table (mpm_particles), raw, under the component's own
    !> name, in table order; a field with no values per particle (no material state) is left
    !> out.
    subroutine write_particles(group, particles, error)
        type(hdf5_location_type), intent(in) :: group
        type(particles_type), intent(in) :: particles
        type(error_type), allocatable, intent(out) :: error

        type(particle_field_type) :: field
        real(wp), allocatable :: values(:, :), column(:)
        integer, allocatable :: integers(:)
        character(len=:), allocatable :: name, units
        integer :: k, d

        d = particles%dim
        do k = 1, particle_field_count()
            field = particle_field(k)
            if (.not. field%saved .or. .not. field_held(particles, k)) cycle
            if (values_per_particle(field, d, particles%nstate) == 0) cycle
            name = trim(field%name)
            units = field_units(field, d)
            if (field%whole) then
                call get_field_integers(particles, k, integers)
                call hdf5_write_dataset(group, name, integers, error, units=units)
            else
                call get_field(particles, k, values)
                if (field%values == per_particle) then
                    ! (a copy, not a section: the dataset writer takes contiguous arrays)
                    column = values(1, :)
                    call hdf5_write_dataset(group, name, column, error, units=units)
                else if (field%values == per_tensor) then
                    call hdf5_write_dataset(group, name, reshape(values, [d, d, particles%n]), &
                        error, units=units)
                else if (field%voigt) then
                    call hdf5_write_dataset(group, name, values, error, units=units, &
                        components=voigt_components(d))
                else
                    call hdf5_write_dataset(group, name, values, error, units=units)
                end if
            end if
            if (allocated(error)) return
        end do
    end subroutine write_particles

    !> The run group of a checkpoint: sizes as attributes, arrays as datasets (the text of
    !> the case file as its bytes: an attribute holds at most 64 kB).
    subroutine write_run_record(group, run, error)
        type(hdf5_location_type), intent(in) :: group
        type(run_record_type), intent(in) :: run
        type(error_type), allocatable, intent(out) :: error

        integer :: i

        call hdf5_write_attribute(group, "case_file", run%case_file, error)
        if (allocated(error)) return
        call hdf5_write_attribute(group, "output_dir", run%output_dir, error)
        if (allocated(error)) return
        call hdf5_write_attribute(group, "images", run%images, error)
        if (allocated(error)) return
        call hdf5_write_attribute(group, "dt", run%dt, error)
        if (allocated(error)) return
        call hdf5_write_attribute(group, "energy_terms", state_energy_terms, error)
        if (allocated(error)) return
        call hdf5_write_attribute(group, "energy", run%energy, error)
        if (allocated(error)) return
        call hdf5_write_attribute(group, "kinetic_previous", run%kinetic_previous, error)
        if (allocated(error)) return
        call hdf5_write_attribute(group, "next_output", run%next_output, error)
        if (allocated(error)) return
        call hdf5_write_attribute(group, "next_history", run%next_history, error)
        if (allocated(error)) return
        call hdf5_write_attribute(group, "wall", run%wall, error)
        if (allocated(error)) return
        call hdf5_write_attribute(group, "outputs", size(run%output_time), error)
        if (allocated(error)) return
        call hdf5_write_attribute(group, "face_loads", size(run%face_load), error)
        if (allocated(error)) return
        call hdf5_write_attribute(group, "terrain_loads", size(run%terrain_load), error)
        if (allocated(error)) return
        call hdf5_write_attribute(group, "case_text_bytes", len(run%case_text), error)
        if (allocated(error)) return
        call hdf5_write_dataset(group, "case_text", [(iachar(run%case_text(i:i)), &
            i = 1, len(run%case_text))], error, units="byte")
        if (allocated(error)) return
        if (size(run%output_time) > 0) then
            call hdf5_write_dataset(group, "output_time", run%output_time, error, units="s")
            if (allocated(error)) return
            call hdf5_write_dataset(group, "output_step", run%output_step, error, units="-")
            if (allocated(error)) return
            call hdf5_write_dataset(group, "output_counts", reshape(run%output_counts, &
                [size(run%output_counts)]), error, units="-")
            if (allocated(error)) return
            call hdf5_write_dataset(group, "output_id", merge(1, 0, run%output_id), error, &
                units="-")
            if (allocated(error)) return
        end if
        if (size(run%face_load) > 0) then
            call hdf5_write_dataset(group, "face_load", run%face_load, error, units="N s")
            if (allocated(error)) return
        end if
        if (size(run%terrain_load) > 0) then
            call hdf5_write_dataset(group, "terrain_node", run%terrain_node, error, units="-")
            if (allocated(error)) return
            call hdf5_write_dataset(group, "terrain_load", run%terrain_load, error, units="N s")
            if (allocated(error)) return
        end if
        if (allocated(run%acting_disp)) then
            call hdf5_write_attribute(group, "acting_values", size(run%acting_disp), error)
            if (allocated(error)) return
            if (size(run%acting_disp) > 0) then
                call hdf5_write_dataset(group, "acting_disp", run%acting_disp, error, units="m")
                if (allocated(error)) return
            end if
        end if
        if (allocated(run%scatter_order)) then
            call hdf5_write_attribute(group, "scatter_particles", size(run%scatter_order), error)
            if (allocated(error)) return
            call hdf5_write_dataset(group, "scatter_order", run%scatter_order, error, units="-")
        end if
    end subroutine write_run_record

    !> Number of particles of a state file (attribute n), -1 when it cannot be read: a
    !> quick look, before load_state checks the file.
    integer(i8) function state_particle_count(path)
        character(len=*), intent(in) :: path
            !! state file or checkpoint

        type(hdf5_location_type) :: file
        type(error_type), allocatable :: error, ignored
        integer :: n

        state_particle_count = -1
        if (.not. file_exists(path)) return
        call hdf5_initialize(error)
        if (allocated(error)) return
        if (.not. hdf5_is_hdf5_file(path)) return
        call hdf5_open_file(path, file, error)
        if (allocated(error)) return
        if (hdf5_has_attribute(file, "n")) then
            call hdf5_read_attribute(file, "n", n, error)
            if (.not. allocated(error)) state_particle_count = n
        end if
        call hdf5_close(file, ignored)
    end function state_particle_count

    !> The run record of a checkpoint (before its case is known: the record holds it).
    subroutine read_run_record(path, run, error)
        character(len=*), intent(in) :: path
            !! checkpoint file
        type(run_record_type), intent(out) :: run
            !! the record
        type(error_type), allocatable, intent(out) :: error
            !! set (exit_input) when the file is not a checkpoint of mpm-geo

        type(hdf5_location_type) :: file, group

        call open_state_file(path, restart_refusal(path, ""), file, error)
        if (allocated(error)) return
        steps: block
            if (.not. hdf5_has_link(file, "run")) then
                call fatal_error(error, restart_refusal(path, "it is a state file "// &
                    "(save_state), not a checkpoint: start a new run from it with "// &
                    "load_state in the case file"), exit_input)
                exit steps
            end if
            call hdf5_open_group(file, "run", group, error)
            if (allocated(error)) exit steps
            call read_run_group(group, run, error)
            call hdf5_close_after(group, error)
        end block steps
        call hdf5_close_after(file, error)
        if (allocated(error)) then
            if (error%code /= exit_input) error%message = restart_refusal(path, error%message)
            error%code = exit_input
        end if
    end subroutine read_run_record

    subroutine read_run_group(group, run, error)
        type(hdf5_location_type), intent(in) :: group
        type(run_record_type), intent(inout) :: run
        type(error_type), allocatable, intent(out) :: error

        integer :: outputs, faces, terrain, nbytes, i, terms
        integer, allocatable :: bytes(:), counts(:), ids(:)

        call hdf5_read_attribute(group, "case_file", run%case_file, error)
        if (allocated(error)) return
        call hdf5_read_attribute(group, "output_dir", run%output_dir, error)
        if (allocated(error)) return
        call hdf5_read_attribute(group, "images", run%images, error)
        if (allocated(error)) return
        call hdf5_read_attribute(group, "dt", run%dt, error)
        if (allocated(error)) return
        terms = 4
        if (hdf5_has_attribute(group, "energy_terms")) then
            call hdf5_read_attribute(group, "energy_terms", terms, error)
            if (allocated(error)) return
        end if
        if (terms /= state_energy_terms) then
            call fatal_error(error, "its run record keeps "//int_text(terms)// &
                " energy terms, this build "//int_text(state_energy_terms)// &
                " (a checkpoint of an older build, before the energy balance of history.csv:"// &
                " continue it with that build, or start the run again)", exit_input)
            return
        end if
        call hdf5_read_attribute(group, "energy", run%energy, error)
        if (allocated(error)) return
        call hdf5_read_attribute(group, "kinetic_previous", run%kinetic_previous, error)
        if (allocated(error)) return
        call hdf5_read_attribute(group, "next_output", run%next_output, error)
        if (allocated(error)) return
        call hdf5_read_attribute(group, "next_history", run%next_history, error)
        if (allocated(error)) return
        call hdf5_read_attribute(group, "wall", run%wall, error)
        if (allocated(error)) return
        call hdf5_read_attribute(group, "outputs", outputs, error)
        if (allocated(error)) return
        call hdf5_read_attribute(group, "face_loads", faces, error)
        if (allocated(error)) return
        call hdf5_read_attribute(group, "terrain_loads", terrain, error)
        if (allocated(error)) return
        if (run%images < 1 .or. outputs < 0 .or. faces < 0 .or. terrain < 0) then
            call fatal_error(error, "the run record is damaged (images "// &
                int_text(run%images)//", outputs "//int_text(outputs)//")", exit_input)
            return
        end if
        call hdf5_read_attribute(group, "case_text_bytes", nbytes, error)
        if (allocated(error)) return
        if (nbytes < 0) then
            call fatal_error(error, "the run record is damaged (case_text_bytes "// &
                int_text(nbytes)//")", exit_input)
            return
        end if
        allocate (bytes(nbytes))
        allocate (character(len=nbytes) :: run%case_text)
        call hdf5_read_dataset(group, "case_text", bytes, error)
        if (allocated(error)) return
        do i = 1, nbytes
            run%case_text(i:i) = achar(bytes(i))
        end do
        allocate (run%output_time(outputs), run%output_step(outputs), &
            run%output_counts(run%images, outputs), run%output_id(outputs), &
            run%face_load(faces), run%terrain_node(terrain), run%terrain_load(terrain))
        if (outputs > 0) then
            call hdf5_read_dataset(group, "output_time", run%output_time, error)
            if (allocated(error)) return
            call hdf5_read_dataset(group, "output_step", run%output_step, error)
            if (allocated(error)) return
            allocate (counts(run%images*outputs), ids(outputs))
            call hdf5_read_dataset(group, "output_counts", counts, error)
            if (allocated(error)) return
            run%output_counts = reshape(counts, [run%images, outputs])
            call hdf5_read_dataset(group, "output_id", ids, error)
            if (allocated(error)) return
            run%output_id = ids /= 0
        end if
        if (faces > 0) then
            call hdf5_read_dataset(group, "face_load", run%face_load, error)
            if (allocated(error)) return
        end if
        if (terrain > 0) then
            call hdf5_read_dataset(group, "terrain_node", run%terrain_node, error)
            if (allocated(error)) return
            call hdf5_read_dataset(group, "terrain_load", run%terrain_load, error)
            if (allocated(error)) return
        end if
        if (hdf5_has_attribute(group, "acting_values")) then
            call hdf5_read_attribute(group, "acting_values", nbytes, error)
            if (allocated(error)) return
            if (nbytes < 0) then
                call fatal_error(error, "the run record is damaged (acting_values "// &
                    int_text(nbytes)//")", exit_input)
                return
            end if
            allocate (run%acting_disp(nbytes))
            if (nbytes > 0) then
                call hdf5_read_dataset(group, "acting_disp", run%acting_disp, error)
                if (allocated(error)) return
            end if
        end if
        if (hdf5_has_attribute(group, "scatter_particles")) then
            call hdf5_read_attribute(group, "scatter_particles", nbytes, error)
            if (allocated(error)) return
            if (nbytes < 0) then
                call fatal_error(error, "the run record is damaged (scatter_particles "// &
                    int_text(nbytes)//")", exit_input)
                return
            end if
            allocate (run%scatter_order(nbytes))
            call hdf5_read_dataset(group, "scatter_order", run%scatter_order, error)
        end if
    end subroutine read_run_group

    !> Open a state file or checkpoint after checking that it is one this build reads: it
    !> exists, is HDF5, and has the format and format_version of save_state.
    subroutine open_state_file(path, prefix, file, error)
        character(len=*), intent(in) :: path
            !! the file
        character(len=*), intent(in) :: prefix
            !! start of every refusal ("cannot load the state file 'PATH': ")
        type(hdf5_location_type), intent(out) :: file
            !! the open file (closed again on a refusal)
        type(error_type), allocatable, intent(out) :: error
            !! set (exit_input) when the file is refused

        character(len=:), allocatable :: format
        integer :: version
        type(error_type), allocatable :: ignored

        if (directory_exists(path)) then
            call fatal_error(error, prefix//"it is a folder, not a file", exit_input)
            return
        end if
        if (.not. file_exists(path)) then
            call fatal_error(error, prefix//"the file does not exist", exit_input)
            return
        end if
        call hdf5_initialize(error)
        if (allocated(error)) return
        if (.not. hdf5_is_hdf5_file(path)) then
            call fatal_error(error, prefix//"it is not an HDF5 file", exit_input)
            return
        end if
        call hdf5_open_file(path, file, error)
        if (allocated(error)) return
        steps: block
            format = ""
            if (hdf5_has_attribute(file, "format")) then
                call hdf5_read_attribute(file, "format", format, error)
                if (allocated(error)) exit steps
            end if
            if (format /= state_format) then
                call fatal_error(error, prefix//"it is not an mpm-geo state file or "// &
                    "checkpoint (format '"//format//"', expected '"//state_format// &
                    "'; an output file of a run is neither)", exit_input)
                exit steps
            end if
            call hdf5_read_attribute(file, "format_version", version, error)
            if (allocated(error)) exit steps
            if (version /= state_format_version) then
                call fatal_error(error, prefix//"format_version "//int_text(version)// &
                    " is not supported (this build reads format_version "// &
                    int_text(state_format_version)//")", exit_input)
            end if
        end block steps
        if (allocated(error)) call hdf5_close(file, ignored)
    end subroutine open_state_file

    pure function restart_refusal(path, reason) result(message)
        character(len=*), intent(in) :: path, reason
        character(len=:), allocatable :: message

        message = "cannot restart from '"//path//"': "//reason
    end function restart_refusal

    !> Read a state file written by save_state, after checking that it fits the case.
    subroutine load_state(path, case, particles, time, step, error, nstate)
        character(len=*), intent(in) :: path
            !! state file
        type(case_type), intent(in) :: case
            !! the case to continue: grid and material names must match the state's
        type(particles_type), intent(out) :: particles
            !! particles read, material indices remapped to the case's order
        real(wp), intent(out) :: time
            !! simulated time of the state [s]
        integer, intent(out) :: step
            !! time step number of the state
        type(error_type), allocatable, intent(out) :: error
            !! set (code exit_input) when the file is not a state of this case
        integer, intent(in), optional :: nstate
            !! material state variables the case needs per particle (default 0)

        type(hdf5_location_type) :: file

        time = 0.0_wp
        step = 0
        call open_state_file(path, refusal(path, ""), file, error)
        if (allocated(error)) return
        call read_state_file(path, file, case, particles, time, step, error, nstate)
        call hdf5_close_after(file, error)
    end subroutine load_state

    subroutine read_state_file(path, file, case, particles, time, step, error, nstate)
        character(len=*), intent(in) :: path
        type(hdf5_location_type), intent(in) :: file
        type(case_type), intent(in) :: case
        type(particles_type), intent(out) :: particles
        real(wp), intent(out) :: time
        integer, intent(out) :: step
        type(error_type), allocatable, intent(out) :: error
        integer, intent(in), optional :: nstate

        type(hdf5_location_type) :: group
        character(len=:), allocatable :: format
        type(text_type), allocatable :: names(:), types(:)
        integer, allocatable :: remap(:)
        integer :: dim, n, nstress, file_nstate, case_nstate

        time = 0.0_wp
        step = 0
        call check_grid(path, file, case, dim, error)
        if (allocated(error)) return
        call hdf5_read_attribute(file, "materials", names, error)
        if (allocated(error)) return
        call material_remap(path, names, case, remap, error)
        if (allocated(error)) return

        call hdf5_read_attribute(file, "n", n, error)
        if (allocated(error)) return
        call hdf5_read_attribute(file, "nstress", nstress, error)
        if (allocated(error)) return
        if (n < 0 .or. nstress /= nstress_of(dim)) then
            call fatal_error(error, refusal(path, "n = "//int_text(n)//" and nstress = "// &
                int_text(nstress)//" are not valid for dimension "//int_text(dim)), exit_input)
            return
        end if
        call hdf5_read_attribute(file, "time", time, error)
        if (allocated(error)) return
        call hdf5_read_attribute(file, "step", step, error)
        if (allocated(error)) return

        ! material state: the file's variables, padded with zeros to what the case's materials
        ! need (an elastic geostatic stage may precede a plastic run)
        file_nstate = 0
        if (hdf5_has_attribute(file, "nstate")) then
            call hdf5_read_attribute(file, "nstate", file_nstate, error)
            if (allocated(error)) return
        end if
        case_nstate = 0
        if (present(nstate)) case_nstate = nstate
        call new_particles(particles, dim, n, error, max(file_nstate, case_nstate))
        if (allocated(error)) return
        call hdf5_open_group(file, "particles", group, error)
        if (allocated(error)) return
        call read_particles(group, particles, file_nstate, error)
        call hdf5_close_after(group, error)
        if (allocated(error)) return

        if (hdf5_has_attribute(file, "material_types") .and. particles%nstate > 0) then
            call hdf5_read_attribute(file, "material_types", types, error)
            if (allocated(error)) return
            call forget_other_laws(types, remap, case, particles)
        end if
        call apply_remap(path, remap, particles, error)
        if (allocated(error)) return
        call check_inside(path, case, particles, error)
    end subroutine read_state_file

    !> The material state of a particle whose material has another type in the loading case
    !> (a Mohr-Coulomb stage, then a Cam Clay one of the same name) means something else to the
    !> new law: it starts afresh, zero (the plastic strains of the earlier law are not the
    !> new one's; a Cam Clay preconsolidation pressure of zero is set from the stress at the
    !> first update). Material indices are still the file's.
    subroutine forget_other_laws(types, remap, case, particles)
        type(text_type), intent(in) :: types(:)
            !! material types of the state, in the saving case's order
        integer, intent(in) :: remap(:)
            !! index in the case of each material of the state
        type(case_type), intent(in) :: case
            !! the loading case
        type(particles_type), intent(inout) :: particles
            !! particles read, material indices as in the file

        logical :: changed(size(remap))
        integer :: k, p

        do k = 1, size(remap)
            changed(k) = .false.
            if (k > size(types)) cycle
            if (.not. allocated(case%materials(remap(k))%type) .or. types(k)%text == "") cycle
            changed(k) = types(k)%text /= case%materials(remap(k))%type
        end do
        if (.not. any(changed)) return
        do p = 1, particles%n
            if (particles%material(p) < 1 .or. particles%material(p) > size(remap)) cycle
            if (changed(particles%material(p))) particles%state(:, p) = 0.0_wp
        end do
    end subroutine forget_other_laws

    !> The saved arrays of the field table, in table order. A field the particles do not hold
    !> by default (APIC affine velocities) is allocated when the file has it; one held always
    !> is required, except the material state of a file without any; the others are zero
    !> when missing (a checkpoint of a run that keeps no displacement or strain). The
    !> material state of the file fills the first of the case's variables (an elastic
    !> geostatic stage may precede a plastic run).
    subroutine read_particles(group, particles, file_nstate, error)
        type(hdf5_location_type), intent(in) :: group
        type(particles_type), intent(inout) :: particles
        integer, intent(in) :: file_nstate
            !! material state variables per particle in the file
        type(error_type), allocatable, intent(out) :: error

        type(particle_field_type) :: field
        real(wp), allocatable :: values1(:), values2(:, :), values3(:, :, :)
        integer, allocatable :: integers(:)
        character(len=:), allocatable :: name
        integer :: k, d, n, rows

        d = particles%dim
        n = particles%n
        do k = 1, particle_field_count()
            field = particle_field(k)
            if (.not. field%saved) cycle
            name = trim(field%name)
            rows = values_per_particle(field, d, file_nstate)
            if (rows == 0) cycle
            if (.not. hdf5_has_link(group, name) .and. field%held /= held_always) cycle
            if (.not. field_held(particles, k)) then
                call hold_field(particles, k, error)
                if (allocated(error)) return
            end if
            if (field%whole) then
                allocate (integers(n))
                call hdf5_read_dataset(group, name, integers, error)
                if (.not. allocated(error)) call put_field_integers(particles, k, integers)
                deallocate (integers)
            else if (field%values == per_particle) then
                allocate (values1(n))
                call hdf5_read_dataset(group, name, values1, error)
                if (.not. allocated(error)) call put_field(particles, k, reshape(values1, [1, n]))
                deallocate (values1)
            else if (field%values == per_tensor) then
                allocate (values3(d, d, n))
                call hdf5_read_dataset(group, name, values3, error)
                if (.not. allocated(error)) call put_field(particles, k, reshape(values3, [rows, n]))
                deallocate (values3)
            else
                allocate (values2(rows, n))
                call hdf5_read_dataset(group, name, values2, error)
                if (.not. allocated(error)) call put_field(particles, k, values2)
                deallocate (values2)
            end if
            if (allocated(error)) return
        end do
    end subroutine read_particles

    !> Refuse a state whose grid (dimension, ncells, dx, origin) is not the case's.
    subroutine check_grid(path, file, case, dim, error)
        character(len=*), intent(in) :: path
        type(hdf5_location_type), intent(in) :: file
        type(case_type), intent(in) :: case
        integer, intent(out) :: dim
            !! dimension of the state (= the case's when no error)
        type(error_type), allocatable, intent(out) :: error

        integer :: ncells(3), d
        real(wp) :: dx, origin(3)

        call hdf5_read_attribute(file, "dimension", dim, error)
        if (allocated(error)) return
        if (dim /= case%dim) then
            call fatal_error(error, refusal(path, "the state has dimension "// &
                int_text(dim)//" but the case has dimension "//int_text(case%dim)), exit_input)
            return
        end if
        call hdf5_read_attribute(file, "ncells", ncells, error)
        if (allocated(error)) return
        call hdf5_read_attribute(file, "dx", dx, error)
        if (allocated(error)) return
        call hdf5_read_attribute(file, "origin", origin, error)
        if (allocated(error)) return

        if (any(ncells(1:dim) /= case%domain%ncells(1:dim))) then
            call fatal_error(error, refusal(path, "the state grid has ncells = "// &
                ints_text(ncells(1:dim))//" but the case has ncells = "// &
                ints_text(case%domain%ncells(1:dim))), exit_input)
            return
        end if
        if (.not. close_enough(dx, case%domain%dx, 0.0_wp)) then
            call fatal_error(error, refusal(path, "the state grid has dx = "// &
                real_text(dx)//" m but the case has dx = "//real_text(case%domain%dx)//" m"), &
                exit_input)
            return
        end if
        do d = 1, dim
            if (.not. close_enough(origin(d), case%domain%origin(d), case%domain%dx)) then
                call fatal_error(error, refusal(path, "the state grid has origin = "// &
                    reals_text(origin(1:dim))//" m but the case has origin = "// &
                    reals_text(case%domain%origin(1:dim))//" m"), exit_input)
                return
            end if
        end do
    end subroutine check_grid

    !> Index in the case of each material of the state, by name.
    subroutine material_remap(path, names, case, remap, error)
        character(len=*), intent(in) :: path
        type(text_type), intent(in) :: names(:)
            !! material names of the state, in the saving case's order
        type(case_type), intent(in) :: case
        integer, allocatable, intent(out) :: remap(:)
            !! remap(k) = index in case%materials of the state's material k
        type(error_type), allocatable, intent(out) :: error

        integer :: k, m, ncase
        character(len=:), allocatable :: known

        ncase = 0
        if (allocated(case%materials)) ncase = size(case%materials)
        allocate (remap(size(names)))
        remap = 0
        do k = 1, size(names)
            do m = 1, ncase
                if (.not. allocated(case%materials(m)%name)) cycle
                if (case%materials(m)%name == names(k)%text) then
                    remap(k) = m
                    exit
                end if
            end do
            if (remap(k) == 0) then
                known = ""
                do m = 1, ncase
                    if (.not. allocated(case%materials(m)%name)) cycle
                    if (len(known) > 0) known = known//", "
                    known = known//"'"//case%materials(m)%name//"'"
                end do
                if (len(known) == 0) known = "none"
                call fatal_error(error, refusal(path, "material '"//names(k)%text// &
                    "' of the state is not a material of the case (the case has: "// &
                    known//")"), exit_input)
                return
            end if
        end do
    end subroutine material_remap

    subroutine apply_remap(path, remap, particles, error)
        character(len=*), intent(in) :: path
        integer, intent(in) :: remap(:)
        type(particles_type), intent(inout) :: particles
        type(error_type), allocatable, intent(out) :: error

        integer :: p

        do p = 1, particles%n
            if (particles%material(p) < 1 .or. particles%material(p) > size(remap)) then
                call fatal_error(error, refusal(path, "particle "//int_text(p)// &
                    " has material index "//int_text(particles%material(p))// &
                    ", outside 1.."//int_text(size(remap))//" (damaged file?)"), exit_input)
                return
            end if
            particles%material(p) = remap(particles%material(p))
        end do
    end subroutine apply_remap

    !> Refuse a state with a particle outside the case's domain (boundary included).
    subroutine check_inside(path, case, particles, error)
        character(len=*), intent(in) :: path
        type(case_type), intent(in) :: case
        type(particles_type), intent(in) :: particles
        type(error_type), allocatable, intent(out) :: error

        integer :: p, d, k
        real(wp) :: upper(3)
        character(len=:), allocatable :: box

        upper = case%domain%origin + real(case%domain%ncells, wp)*case%domain%dx
        do p = 1, particles%n
            do d = 1, case%dim
                ! written so that a NaN position counts as outside
                if (.not. (particles%x(d, p) >= case%domain%origin(d) .and. &
                    particles%x(d, p) <= upper(d))) then
                    box = ""
                    do k = 1, case%dim
                        if (k > 1) box = box//" x "
                        box = box//"["//real_text(case%domain%origin(k))//", "//real_text(upper(k))//"]"
                    end do
                    call fatal_error(error, refusal(path, "particle "//int_text(p)//" at "// &
                        reals_text(particles%x(:, p))//" m lies outside the case domain "// &
                        box//" m"), exit_input)
                    return
                end if
            end do
        end do
    end subroutine check_inside

    !> Material types of a case ("mohr_coulomb", ...), in case order ("" for a material made
    !> in code without one).
    function material_types(case) result(types)
        type(case_type), intent(in) :: case
        type(text_type), allocatable :: types(:)

        integer :: m, nmat

        nmat = 0
        if (allocated(case%materials)) nmat = size(case%materials)
        allocate (types(nmat))
        do m = 1, nmat
            types(m)%text = ""
            if (allocated(case%materials(m)%type)) types(m)%text = case%materials(m)%type
        end do
    end function material_types

    !> Material names of a case, in case order.
    function material_names(case) result(names)
        type(case_type), intent(in) :: case
        type(text_type), allocatable :: names(:)

        integer :: m, nmat

        nmat = 0
        if (allocated(case%materials)) nmat = size(case%materials)
        allocate (names(nmat))
        do m = 1, nmat
            names(m)%text = ""
            if (allocated(case%materials(m)%name)) names(m)%text = case%materials(m)%name
        end do
    end function material_names

    !> Names of the stored Voigt components, as the "components" attribute of stress and strain.
    pure function voigt_components(dim) result(text)
        integer, intent(in) :: dim
        character(len=:), allocatable :: text

        if (dim == 2) then
            text = "xx yy zz xy"
        else
            text = "xx yy zz xy yz zx"
        end if
    end function voigt_components

    !> Equal within grid_rtol relative to the larger magnitude (or to `scale`).
    pure logical function close_enough(a, b, scale)
        real(wp), intent(in) :: a, b
        real(wp), intent(in) :: scale
            !! length of the problem, so that origins near 0 compare sensibly [m]

        close_enough = abs(a - b) <= grid_rtol*max(abs(a), abs(b), abs(scale))
    end function close_enough

    pure function refusal(path, reason) result(message)
        character(len=*), intent(in) :: path, reason
        character(len=:), allocatable :: message

        message = "cannot load the state file '"//path//"': "//reason
    end function refusal

    pure function ints_text(values) result(text)
        integer, intent(in) :: values(:)
        character(len=:), allocatable :: text

        integer :: i

        text = ""
        do i = 1, size(values)
            if (i > 1) text = text//" "
            text = text//int_text(values(i))
        end do
    end function ints_text

end module mpm_state
