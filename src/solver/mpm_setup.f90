!> The set-up of a simulation: the files a case names (a state file to start from, a
!> checkpoint to continue, the STL terrain surface) are read here, and the solver
!> (mpm_solver::new_simulation) receives their data; the solver reads no file.
module mpm_setup
    use mpm_error, only: error_type
    use mpm_case, only: case_type
    use mpm_stl, only: read_stl
    use mpm_surface_mesh, only: stl_mesh_type
    use mpm_state, only: load_state
    use mpm_case_materials, only: state_variable_count
    use mpm_solver, only: simulation_type, new_simulation, start_type, has_text
    implicit none
    private
    public :: read_start, start_simulation

contains

    !> Read the files a case starts from: the particles of a checkpoint (`restart`) or of the
    !> case's load_state, and the terrain surface of contact.type = "terrain_stl". Every image
    !> reads them whole.
    subroutine read_start(case, start, error, restart)
        type(case_type), intent(in) :: case
            !! resolved case
        type(start_type), intent(out) :: start
            !! what the files hold
        type(error_type), allocatable, intent(out) :: error
            !! set when a file is refused (its message names the case, key and file)
        character(len=*), intent(in), optional :: restart
            !! checkpoint to continue from: its particles, time and step

        type(stl_mesh_type) :: mesh
        integer :: nstate

        if (present(restart) .or. has_text(case%load_state)) then
            ! the state variables the case's materials need per particle
            nstate = state_variable_count(case%materials)
            start%loaded = .true.
            if (present(restart)) then
                start%restart = .true.
                call load_state(restart, case, start%particles, start%time, start%step, error, &
                    nstate)
                if (allocated(error)) return
            else
                call load_state(case%load_state, case, start%particles, start%time, start%step, &
                    error, nstate)
                if (allocated(error)) then
                    ! which case and key asked for the file
                    error%message = case%file//": load_state: "//error%message
                    return
                end if
            end if
        end if
        if (case%contact%type == "terrain_stl") then
            call read_stl(case%contact%file, mesh, error, case%contact%scale, &
                case%contact%offset, key="contact.file")
            if (allocated(error)) then
                error%message = case%file//": "//error%message
                return
            end if
            call move_alloc(mesh%vertex, start%terrain_corner)
        end if
    end subroutine read_start

    !> Read the files of a case (read_start) and build its simulation (new_simulation).
    subroutine start_simulation(sim, case, error, restart)
        type(simulation_type), intent(out) :: sim
            !! the simulation
        type(case_type), intent(in) :: case
            !! resolved case
        type(error_type), allocatable, intent(out) :: error
            !! set when a file is refused or the model cannot be built
        character(len=*), intent(in), optional :: restart
            !! checkpoint to continue from

        type(start_type) :: start

        call read_start(case, start, error, restart)
        if (allocated(error)) return
        call new_simulation(sim, case, error, start)
    end subroutine start_simulation

end module mpm_setup
