!> The `solver` key of a case: update scheme, shape function and velocity transfer.
module mpm_case_solver
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_case_cursor, only: cursor_type
    implicit none
    private
    public :: solver_section_type, read_solver, solver_keys
    public :: scheme_usf, scheme_usl, scheme_musl, scheme_names
    public :: shape_linear, shape_cpgimp, shape_names

    ! Update scheme (when the stress is updated within a step)
    integer, parameter :: scheme_usf = 1   !! update stress first
    integer, parameter :: scheme_usl = 2   !! update stress last
    integer, parameter :: scheme_musl = 3  !! modified update stress last
    character(len=*), parameter :: scheme_names(3) = [character(len=4) :: "USF", "USL", "MUSL"]
        !! name of each scheme in the case file

    ! Shape function
    integer, parameter :: shape_linear = 1  !! bilinear / trilinear hat functions
    integer, parameter :: shape_cpgimp = 2  !! contiguous-particle GIMP
    character(len=*), parameter :: shape_names(2) = [character(len=6) :: "linear", "cpgimp"]
        !! name of each shape function in the case file

    character(len=*), parameter :: solver_keys(*) = [character(len=18) :: "scheme", &
        "shape_function", "locking_correction", "transfer", "flip_fraction"]
        !! keys of `solver`

    !> `solver`: how a step is computed.
    type :: solver_section_type
        integer :: scheme = scheme_musl
            !! update scheme
        integer :: shape = shape_cpgimp
            !! shape function
        logical :: apic = .false.
            !! affine particle-in-cell transfer (solver.transfer = "apic") instead of FLIP
        real(wp) :: flip_fraction = 1.0_wp
            !! particle velocity update: this fraction FLIP (v_p + dt a), the rest PIC (the
            !! nodal velocity interpolated) [-]
        logical :: fbar = .false.
            !! F-bar volumetric locking correction: the volume change of each step is averaged
            !! over the particles of a cell (solver.locking_correction = "fbar")
    end type solver_section_type

contains

    !> `solver`: update scheme and shape function.
    subroutine read_solver(root, solver, error)
        type(cursor_type), intent(in) :: root
            !! top-level object
        type(solver_section_type), intent(inout) :: solver
            !! the solver section
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: cur
        logical :: found
        integer :: choice

        call root%get_section("solver", solver_keys, cur, error, found=found)
        if (allocated(error) .or. .not. found) return
        call cur%get_choice("scheme", scheme_names, [scheme_usf, scheme_usl, scheme_musl], &
            solver%scheme, error)
        if (allocated(error)) return
        call cur%get_choice("shape_function", [character(len=6) :: shape_names, "gimp"], &
            [shape_linear, shape_cpgimp, shape_cpgimp], solver%shape, error)
        if (allocated(error)) return
        choice = merge(1, 0, solver%fbar)
        call cur%get_choice("locking_correction", [character(len=4) :: "none", "fbar"], [0, 1], &
            choice, error)
        solver%fbar = choice == 1
        if (allocated(error)) return
        choice = merge(1, 0, solver%apic)
        call cur%get_choice("transfer", [character(len=4) :: "flip", "apic"], [0, 1], choice, &
            error)
        if (allocated(error)) return
        solver%apic = choice == 1
        call cur%get_real("flip_fraction", solver%flip_fraction, error, at_least=0.0_wp, &
            at_most=1.0_wp, unit="-", found=found)
        if (allocated(error)) return
        if (found .and. solver%apic) then
            call cur%fail(error, "solver.flip_fraction applies to solver.transfer = " &
                //'"flip" only (here "apic", whose velocity update has no FLIP part); remove it')
        end if
    end subroutine read_solver

end module mpm_case_solver
