!> The 1D large-deformation manufactured solution (REFERENCES.md section 3; Steffen, Kirby
!> and Berzins 2008), run as a one-cell strip of neo-Hookean material (nu = 0) between fixed
!> ends, with sliding top and bottom faces.
!>
!>     u(X, t) = A sin(2 pi X / L) cos(c pi t / L),   c = sqrt(E / rho0)
!>     F = 1 + (2 A pi / L) cos(2 pi X / L) cos(c pi t / L),  sigma = E/2 (F - 1/F)
!>     b = (c pi / L)^2 u (1 + 2 / F^2), at each particle's reference position X
!>
!> The particles start displaced, u(X, 0), with the matching F, volume, size and stress, and at
!> rest. Errors: L2 = sqrt(mean_p (u_p - u(X_p, t))^2) and the maximum.
module mpm_manufactured
    use mpm_kinds, only: wp
    use mpm_strings, only: int_text
    use mpm_error, only: error_type
    use mpm_clock, only: wall_time
    use mpm_case, only: case_type, read_case_string
    use mpm_solver, only: simulation_type, new_simulation, advance, stable_time_step
    implicit none
    private
    public :: mms_result_type, run_manufactured, mms_displacement

    real(wp), parameter :: pi = acos(-1.0_wp)
    real(wp), parameter :: young = 1.0e4_wp
        !! Young's modulus of the strip [Pa]
    real(wp), parameter :: density = 1.0_wp
        !! reference density [kg/m3]
    real(wp), parameter :: length = 1.0_wp
        !! length L of the strip [m]

    !> Errors and cost of one run.
    type :: mms_result_type
        real(wp) :: error_l2 = 0.0_wp
            !! root-mean-square displacement error at the end [m]
        real(wp) :: error_max = 0.0_wp
            !! largest displacement error at the end [m]
        real(wp) :: wall = 0.0_wp
            !! wall time of the time loop [s]
        integer :: steps = 0
            !! time steps
        integer :: particles = 0
            !! particles
    end type mms_result_type

contains

    !> Exact displacement u(X, t) [m].
    pure elemental real(wp) function mms_displacement(x, t, amplitude)
        real(wp), intent(in) :: x
            !! reference position X [m]
        real(wp), intent(in) :: t
            !! time [s]
        real(wp), intent(in) :: amplitude
            !! A [m]
        mms_displacement = amplitude*sin(2*pi*x/length)*cos(sqrt(young/density)*pi*t/length)
    end function mms_displacement

    !> Exact deformation gradient F(X, t) [-].
    pure elemental real(wp) function mms_stretch(x, t, amplitude)
        real(wp), intent(in) :: x, t, amplitude
        mms_stretch = 1.0_wp + 2*amplitude*pi/length*cos(2*pi*x/length) &
            *cos(sqrt(young/density)*pi*t/length)
    end function mms_stretch

    !> Run the manufactured solution with `ncells` cells along the strip to time `tend`.
    subroutine run_manufactured(ncells, shape, scheme, amplitude, tend, cfl, ppc, result, error)
        integer, intent(in) :: ncells
            !! cells along the strip
        character(len=*), intent(in) :: shape
            !! "linear" or "cpgimp"
        character(len=*), intent(in) :: scheme
            !! "USF", "USL" or "MUSL"
        real(wp), intent(in) :: amplitude
            !! A [m] (0.05 in the reference; smaller for the small-deformation regime)
        real(wp), intent(in) :: tend
            !! end time [s]
        real(wp), intent(in) :: cfl
            !! CFL factor [-]
        integer, intent(in) :: ppc
            !! particles per cell along each direction
        type(mms_result_type), intent(out) :: result
            !! errors and cost
        type(error_type), allocatable, intent(out) :: error
            !! set when the case is invalid or the run fails

        type(case_type) :: case
        type(simulation_type) :: sim
        real(wp), allocatable :: x_ref(:)
        real(wp) :: dx, f0, c, t0, dt, b
        character(len=64) :: buf
        integer :: p, a

        dx = length/ncells
        c = sqrt(young/density)
        write (buf, "(es23.16)") dx
        buf = adjustl(buf)
        ! one extra cell on each side keeps the fixed ends on grid nodes inside the domain
        call read_case_string('{"name": "mms", "domain": {"nx": '//int_text(ncells + 2)// &
            ', "ny": 1, "dx": '//trim(buf)//', "origin": [-'//trim(buf)//", 0], "// &
            '"boundaries": {"ymin": "sliding", "ymax": "sliding"}}, '// &
            '"particles": {"ppc": '//int_text(ppc)//'}, "materials": [{"name": "m", '// &
            '"type": "neo_hookean", "E": 1e4, "nu": 0, "rho": 1}], "bodies": [{"material": '// &
            '"m", "min": [0, 0], "max": [1, '//trim(buf)//']}], "solver": {"scheme": "'// &
            scheme//'", "shape_function": "'//shape//'"}, "time": {"tend": 1e3, "cfl": '// &
            trim(real_text(cfl))//"}}", case, error, "manufactured solution")
        if (allocated(error)) return
        call new_simulation(sim, case, error)
        if (allocated(error)) return
        associate (pt => sim%particles)
            allocate (x_ref(pt%n), pt%body_force(pt%dim, pt%n))
            pt%body_force = 0.0_wp
            x_ref = pt%x(1, :)
            do p = 1, pt%n
                f0 = mms_stretch(x_ref(p), 0.0_wp, amplitude)
                pt%x(1, p) = x_ref(p) + mms_displacement(x_ref(p), 0.0_wp, amplitude)
                pt%f(1, 1, p) = f0
                pt%volume(p) = f0*pt%volume0(p)
                pt%lp(1, p) = f0*pt%lp0(1, p)
                pt%state(1, p) = f0 - 1.0_wp
                pt%stress(:, p) = 0.0_wp
                pt%stress(1, p) = 0.5_wp*young*(f0 - 1.0_wp/f0)
            end do
            ! the ends are held: the fixed-end nodes are those at X = 0 and X = L
            sim%grid%constrained = .false.
            do p = 1, sim%grid%nnodes
                a = p - 1 - sim%grid%nn(1)*((p - 1)/sim%grid%nn(1))
                if (a == 1 .or. a == ncells + 1) sim%grid%constrained(:, p) = .true.
            end do
            t0 = wall_time()
            do while (sim%time < tend*(1 - 1.0e-12_wp))
                do p = 1, pt%n
                    b = (c*pi/length)**2*mms_displacement(x_ref(p), sim%time, amplitude) &
                        *(1.0_wp + 2.0_wp/mms_stretch(x_ref(p), sim%time, amplitude)**2)
                    pt%body_force(1, p) = b
                end do
                dt = min(stable_time_step(sim), tend - sim%time)
                call advance(sim, dt, error)
                if (allocated(error)) return
            end do
            result%wall = wall_time() - t0
            result%steps = int(sim%step)
            result%particles = pt%n
            result%error_l2 = sqrt(sum((pt%x(1, :) - x_ref &
                - mms_displacement(x_ref, sim%time, amplitude))**2)/pt%n)
            result%error_max = maxval(abs(pt%x(1, :) - x_ref &
                - mms_displacement(x_ref, sim%time, amplitude)))
        end associate
    end subroutine run_manufactured

    pure function real_text(x) result(text)
        real(wp), intent(in) :: x
        character(len=:), allocatable :: text
        character(len=32) :: buf
        write (buf, "(es23.16)") x
        text = trim(adjustl(buf))
    end function real_text

end module mpm_manufactured
