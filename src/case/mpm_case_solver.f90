!> The `solver` key of a case: update scheme, shape function and velocity transfer.
module mpm_case_solver
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_strings, only: lower, int_text
    use mpm_case_cursor, only: cursor_type
    implicit none
    private
    public :: solver_section_type, read_solver, solver_keys
    public :: scheme_usf, scheme_usl, scheme_musl, scheme_names

    ! Update scheme (when the stress is updated within a step)
    integer, parameter :: scheme_usf = 1   !! update stress first
    integer, parameter :: scheme_usl = 2   !! update stress last
    integer, parameter :: scheme_musl = 3  !! modified update stress last
    character(len=*), parameter :: scheme_names(3) = [character(len=4) :: "USF", "USL", "MUSL"]
        !! name of each scheme in the case file

    integer, parameter :: shape_function_width = 32
        !! longest value of solver.shape_function kept

    character(len=*), parameter :: solver_keys(*) = [character(len=18) :: "scheme", &
        "shape_function", "locking_correction", "transfer", "flip_fraction", "xpic_order", &
        "one_pass"]
        !! keys of `solver`

    !> `solver`: how a step is computed.
    type :: solver_section_type
        integer :: scheme = scheme_musl
            !! update scheme
        character(len=shape_function_width) :: shape_function = "cpgimp"
            !! name of the shape function, in lower case: the registry of the shape functions
            !! (mpm_shape_factory, above the case layer) checks it
        logical :: apic = .false.
            !! affine particle-in-cell transfer (solver.transfer = "apic") instead of FLIP
        logical :: xpic = .false.
            !! XPIC(m) transfer (solver.transfer = "xpic", Hammerquist and Nairn 2017): the FLIP
            !! update of the particles' start velocities with their null-space part removed
        integer :: xpic_order = 2
            !! m of XPIC(m): 1 is PIC; larger keeps more of FLIP and still filters the null
            !! space (solver.xpic_order, 1 to 10)
        real(wp) :: flip_fraction = 1.0_wp
            !! particle velocity update: this fraction FLIP (v_p + dt a), the rest PIC (the
            !! nodal velocity interpolated) [-]
        logical :: fbar = .false.
            !! F-bar volumetric locking correction: the volume change of each step is averaged
            !! over the particles of a cell (solver.locking_correction = "fbar")
        logical :: one_pass = .true.
            !! USL and MUSL without F-bar on one image: the last particle pass of a step also
            !! scatters the next step's P2G (solver.one_pass; false: a P2G pass of its own)
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
        character(len=:), allocatable :: name

        call root%get_section("solver", solver_keys, cur, error, found=found)
        if (allocated(error) .or. .not. found) return
        call cur%get_choice("scheme", scheme_names, [scheme_usf, scheme_usl, scheme_musl], &
            solver%scheme, error)
        if (allocated(error)) return
        name = trim(solver%shape_function)
        call cur%get_string("shape_function", name, error)
        if (allocated(error)) return
        if (len(name) > shape_function_width) then
            call cur%fail(error, cur%key_path("shape_function")//' = "'//name(1:20)// &
                '..." is not allowed: longer than any shape function name (' &
                //int_text(shape_function_width)//" characters at most)")
            return
        end if
        solver%shape_function = lower(name)
        choice = merge(1, 0, solver%fbar)
        call cur%get_choice("locking_correction", [character(len=4) :: "none", "fbar"], [0, 1], &
            choice, error)
        solver%fbar = choice == 1
        if (allocated(error)) return
        choice = merge(1, 0, solver%apic)
        if (solver%xpic) choice = 2
        call cur%get_choice("transfer", [character(len=4) :: "flip", "apic", "xpic"], [0, 1, 2], &
            choice, error)
        if (allocated(error)) return
        solver%apic = choice == 1
        solver%xpic = choice == 2
        call cur%get_real("flip_fraction", solver%flip_fraction, error, at_least=0.0_wp, &
            at_most=1.0_wp, unit="-", found=found)
        if (allocated(error)) return
        if (found .and. solver%apic) then
            call cur%fail(error, "solver.flip_fraction applies to solver.transfer = " &
                //'"flip" only (here "apic", whose velocity update has no FLIP part); remove it')
            return
        end if
        if (found .and. solver%xpic) then
            call cur%fail(error, "solver.flip_fraction applies to solver.transfer = " &
                //'"flip" only (here "xpic", which filters the FLIP update itself: set its ' &
                //"order with solver.xpic_order); remove it")
            return
        end if
        if (cur%has("xpic_order") .and. .not. solver%xpic) then
            call cur%fail(error, 'solver.xpic_order applies to solver.transfer = "xpic" only; ' &
                //'remove it or set "transfer": "xpic"')
            return
        end if
        call cur%get_int("xpic_order", solver%xpic_order, error, at_least=1, at_most=10)
        if (allocated(error)) return
        call cur%get_bool("one_pass", solver%one_pass, error)
    end subroutine read_solver

end module mpm_case_solver
