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
!>
!> The strip is one cell high, so every node lies on the sliding top or bottom face and the
!> transverse velocity is held everywhere: the problem is 1D. Left free, the strip is a beam of
!> depth dx under the compression of the solution (sigma down to -0.39 E at A = 0.05) and
!> buckles, from round-off, at a rate of about 0.3 c / dx: at 256 cells that destroyed the runs
!> within half a period.
!>
!> Also here: the stretched bar (`run_stretched_bar`), which measures the growth of particle
!> velocity noise in a uniformly stressed bar at rest, and `tension_time_step`, the time-step
!> limit that bounds that growth (see docs/accuracy-vs-cost.md). With FLIP, MUSL and USF strain
!> the particles with another nodal velocity than the one that moves them (MUSL: the remapped
!> one; USF: the one of the start of the step); under a tensile stress sigma that mismatch
!> feeds noise at a rate of about sigma dt / (rho0 dx^2). USL strains and moves with the same
!> velocity and shows no growth.
module mpm_manufactured
    use mpm_kinds, only: wp
    use mpm_strings, only: int_text
    use mpm_error, only: error_type, fatal_error
    use mpm_clock, only: wall_time
    use mpm_case, only: case_type, read_case_string
    use mpm_solver, only: simulation_type, new_simulation, advance, stable_time_step, &
        start_energy_balance
    implicit none
    private
    public :: mms_result_type, run_manufactured, new_manufactured, mms_displacement
    public :: bar_result_type, run_stretched_bar, tension_time_step

    real(wp), parameter :: pi = acos(-1.0_wp)
    real(wp), parameter :: young = 1.0e4_wp
        !! Young's modulus of the strip [Pa]
    real(wp), parameter :: density = 1.0_wp
        !! reference density [kg/m3]
    real(wp), parameter :: length = 1.0_wp
        !! length L of the strip [m]
    real(wp), parameter :: noise_speed = 1.0e-3_wp
        !! amplitude of the velocity noise the stretched bar starts with [m/s]
    real(wp), parameter :: noise_cap = 0.1_wp
        !! the stretched bar stops when its rms velocity reaches this (still linear) [m/s]

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

    !> Growth of velocity noise in a uniformly stressed bar at rest.
    type :: bar_result_type
        real(wp) :: stretch = 1.0_wp
            !! stretch F of the bar [-]
        real(wp) :: stress = 0.0_wp
            !! axial Cauchy stress of the bar, tension positive [Pa]
        real(wp) :: dt = 0.0_wp
            !! time step [s]
        real(wp) :: growth = 0.0_wp
            !! growth rate of the rms particle velocity, fitted over the second half [1/s]
        real(wp) :: estimate = 0.0_wp
            !! max(stress, 0) dt / (rho0 dx^2) [1/s]
        real(wp) :: speed_start = 0.0_wp
            !! rms particle velocity at the start [m/s]
        real(wp) :: speed_end = 0.0_wp
            !! rms particle velocity at the end [m/s]
        real(wp) :: time = 0.0_wp
            !! simulated time (shorter than asked when the noise reached noise_cap) [s]
        real(wp) :: wall = 0.0_wp
            !! wall time of the time loop [s]
        integer :: steps = 0
            !! time steps
        integer :: particles = 0
            !! particles
    end type bar_result_type

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

    !> A one-cell strip of cell size L / ncells between ends held at x = 0 and x = L: grid,
    !> material and particles (undeformed, at rest) filling `body_cells` cells from x = 0.
    subroutine new_strip(sim, ncells, body_cells, shape, scheme, cfl, ppc, error)
        type(simulation_type), intent(out) :: sim
        integer, intent(in) :: ncells, body_cells, ppc
        character(len=*), intent(in) :: shape, scheme
        real(wp), intent(in) :: cfl
        type(error_type), allocatable, intent(out) :: error

        type(case_type) :: case
        character(len=:), allocatable :: dx_text
        integer :: i, a

        dx_text = real_text(length/ncells)
        ! one extra cell on each side keeps the fixed ends on grid nodes inside the domain
        call read_case_string('{"name": "mms", "domain": {"nx": '// &
            int_text(max(ncells, body_cells) + 2)//', "ny": 1, "dx": '//dx_text// &
            ', "origin": [-'//dx_text//", 0], "// &
            '"boundaries": {"ymin": "sliding", "ymax": "sliding"}}, '// &
            '"particles": {"ppc": '//int_text(ppc)//'}, "materials": [{"name": "m", '// &
            '"type": "neo_hookean", "E": '//real_text(young)//', "nu": 0, "rho": '// &
            real_text(density)//'}], "bodies": [{"material": "m", "min": [0, 0], "max": ['// &
            real_text(body_cells*(length/ncells))//", "//dx_text//']}], "solver": '// &
            '{"scheme": "'//scheme//'", "shape_function": "'//shape//'"}, '// &
            '"time": {"tend": 1e3, "cfl": '//real_text(cfl)//"}}", case, error, &
            "manufactured solution")
        if (allocated(error)) return
        call new_simulation(sim, case, error)
        if (allocated(error)) return
        ! The sliding faces of the case hold the transverse velocity of every node (the strip
        ! is one cell high); the ends hold the axial one, and so do the nodes beyond them,
        ! which only a particle domain reaching past an end would touch (a wall, not a free
        ! node of nearly no mass).
        do i = 1, sim%grid%nnodes
            a = i - 1 - sim%grid%nn(1)*((i - 1)/sim%grid%nn(1))
            if (a <= 1 .or. a >= ncells + 1) sim%grid%constrained(1, i) = .true.
        end do
    end subroutine new_strip

    !> Set up the manufactured solution with `ncells` cells along the strip, at t = 0.
    subroutine new_manufactured(sim, x_ref, ncells, shape, scheme, amplitude, cfl, ppc, error)
        type(simulation_type), intent(out) :: sim
            !! the model, particles displaced and stressed as the solution at t = 0
        real(wp), allocatable, intent(out) :: x_ref(:)
            !! reference position X of each particle [m]
        integer, intent(in) :: ncells
            !! cells along the strip
        character(len=*), intent(in) :: shape
            !! "linear" or "cpgimp"
        character(len=*), intent(in) :: scheme
            !! "USF", "USL" or "MUSL"
        real(wp), intent(in) :: amplitude
            !! A [m]
        real(wp), intent(in) :: cfl
            !! CFL factor [-]
        integer, intent(in) :: ppc
            !! particles per cell along each direction
        type(error_type), allocatable, intent(out) :: error
            !! set when the case is invalid

        real(wp) :: f0
        integer :: p

        call new_strip(sim, ncells, ncells, shape, scheme, cfl, ppc, error)
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
                pt%state(1, p) = f0 - 1.0_wp
                pt%stress(:, p) = 0.0_wp
                pt%stress(1, p) = 0.5_wp*young*(f0 - 1.0_wp/f0)
            end do
        end associate
        ! the balance starts from the prescribed state
        call start_energy_balance(sim)
    end subroutine new_manufactured

    !> Run the manufactured solution with `ncells` cells along the strip to time `tend`.
    !>
    !> The time step is the solver's CFL step; with `tension_budget` also at most
    !> `tension_time_step(sim, tension_budget, tend)`.
    subroutine run_manufactured(ncells, shape, scheme, amplitude, tend, cfl, ppc, result, error, &
            tension_budget)
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
        real(wp), intent(in), optional :: tension_budget
            !! allowed growth exponent of tension-driven noise over the run [-] (none: no limit)

        type(simulation_type) :: sim
        real(wp), allocatable :: x_ref(:)
        real(wp) :: c, t0, dt
        integer :: p

        call new_manufactured(sim, x_ref, ncells, shape, scheme, amplitude, cfl, ppc, error)
        if (allocated(error)) return
        c = sqrt(young/density)
        associate (pt => sim%particles)
            t0 = wall_time()
            do while (sim%time < tend*(1 - 1.0e-12_wp))
                do p = 1, pt%n
                    pt%body_force(1, p) = (c*pi/length)**2 &
                        *mms_displacement(x_ref(p), sim%time, amplitude) &
                        *(1.0_wp + 2.0_wp/mms_stretch(x_ref(p), sim%time, amplitude)**2)
                end do
                dt = stable_time_step(sim)
                if (present(tension_budget)) dt = min(dt, &
                    tension_time_step(sim, tension_budget, tend))
                dt = min(dt, tend - sim%time)
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

    !> Time-step limit that bounds the tension-driven noise growth of MUSL and USF with FLIP.
    !>
    !> The noise grows at about sigma dt / (rho0 dx^2), sigma the largest tensile normal stress
    !> (measured with `run_stretched_bar`). Taking dt = budget rho0 dx^2 / (sigma duration) at
    !> every step makes that rate budget / duration, so the noise grows by about exp(budget)
    !> over `duration` whatever the history of the stress. Huge when nothing is in tension.
    real(wp) function tension_time_step(sim, budget, duration)
        type(simulation_type), intent(in) :: sim
            !! the simulation
        real(wp), intent(in) :: budget
            !! allowed growth exponent over the duration [-]
        real(wp), intent(in) :: duration
            !! time the bound is for (the length of the run) [s]

        real(wp) :: tension, rho0
        integer :: p, nnormal

        associate (pt => sim%particles)
            nnormal = min(pt%dim, 3)
            tension = 0.0_wp
            rho0 = huge(1.0_wp)
            do p = 1, pt%n
                tension = max(tension, maxval(pt%stress(1:nnormal, p)))
                if (pt%volume0(p) > 0.0_wp) rho0 = min(rho0, pt%mass(p)/pt%volume0(p))
            end do
        end associate
        if (tension <= 0.0_wp .or. budget <= 0.0_wp .or. duration <= 0.0_wp) then
            tension_time_step = huge(1.0_wp)
        else
            tension_time_step = budget*rho0*sim%case%domain%dx**2/(tension*duration)
        end if
    end function tension_time_step

    !> The strip held uniformly stretched (stretch > 1) or compressed at rest between its fixed
    !> ends, with a small pseudo-random particle velocity noise: the growth rate of that noise.
    !>
    !> The particles are made in the reference configuration, nint(ncells / stretch) cells long,
    !> and mapped onto the strip (ncells cells) by x = F X with F = ncells / that number (the
    !> stretch actually used): as in the manufactured solution, their pattern then does not
    !> repeat with the cells.
    subroutine run_stretched_bar(ncells, stretch, shape, scheme, cfl, tend, result, error, &
            tension_budget)
        integer, intent(in) :: ncells
            !! cells along the bar
        real(wp), intent(in) :: stretch
            !! uniform axial stretch F of the bar asked for [-]
        character(len=*), intent(in) :: shape
            !! "linear" or "cpgimp"
        character(len=*), intent(in) :: scheme
            !! "USF", "USL" or "MUSL"
        real(wp), intent(in) :: cfl
            !! CFL factor [-]
        real(wp), intent(in) :: tend
            !! end time [s]
        type(bar_result_type), intent(out) :: result
            !! growth rate, its estimate and cost
        type(error_type), allocatable, intent(out) :: error
            !! set when the case is invalid or the run fails
        real(wp), intent(in), optional :: tension_budget
            !! as in `run_manufactured`

        type(simulation_type) :: sim
        real(wp), allocatable :: times(:), logs(:)
        real(wp) :: t0, dt, speed, f0
        integer :: p, n, first, body_cells

        if (.not. (stretch > 0.0_wp)) then
            call fatal_error(error, "stretched bar: the stretch must be positive")
            return
        end if
        body_cells = max(1, nint(ncells/stretch))
        f0 = real(ncells, wp)/body_cells
        call new_strip(sim, ncells, body_cells, shape, scheme, cfl, 2, error)
        if (allocated(error)) return
        associate (pt => sim%particles)
            pt%x(1, :) = f0*pt%x(1, :)
            pt%volume = f0*pt%volume0
            pt%f(1, 1, :) = f0
            pt%state(1, :) = f0 - 1.0_wp
            pt%stress = 0.0_wp
            pt%stress(1, :) = 0.5_wp*young*(f0 - 1.0_wp/f0)
            do p = 1, pt%n
                ! golden-angle sequence: every wavelength down to the particle spacing
                pt%v(1, p) = noise_speed*sin(2.399963229728653_wp*p)
            end do
            result%stretch = f0
            result%stress = pt%stress(1, 1)
            result%particles = pt%n
            result%speed_start = rms(pt%v(1, :))
            allocate (times(0), logs(0))
            call start_energy_balance(sim)
            t0 = wall_time()
            do while (sim%time < tend*(1 - 1.0e-12_wp))
                dt = stable_time_step(sim)
                if (present(tension_budget)) dt = min(dt, &
                    tension_time_step(sim, tension_budget, tend))
                dt = min(dt, tend - sim%time)
                if (sim%step == 0) result%dt = dt
                call advance(sim, dt, error)
                if (allocated(error)) return
                speed = rms(pt%v(1, :))
                times = [times, sim%time]
                logs = [logs, log(speed)]
                if (speed >= noise_cap) exit
            end do
            result%wall = wall_time() - t0
            result%steps = int(sim%step)
            result%time = sim%time
            result%speed_end = rms(pt%v(1, :))
        end associate
        result%estimate = max(result%stress, 0.0_wp)*result%dt/(density*sim%case%domain%dx**2)
        ! least-squares slope of log(rms speed) over the second half of the run
        n = size(times)
        first = n/2 + 1
        if (n - first >= 1) result%growth = slope(times(first:n), logs(first:n))
    end subroutine run_stretched_bar

    pure real(wp) function rms(values)
        real(wp), intent(in) :: values(:)
        rms = sqrt(sum(values**2)/max(size(values), 1))
    end function rms

    pure real(wp) function slope(x, y)
        real(wp), intent(in) :: x(:), y(:)
        real(wp) :: xm, ym
        xm = sum(x)/size(x)
        ym = sum(y)/size(y)
        slope = sum((x - xm)*(y - ym))/max(sum((x - xm)**2), tiny(1.0_wp))
    end function slope

    pure function real_text(x) result(text)
        real(wp), intent(in) :: x
        character(len=:), allocatable :: text
        character(len=32) :: buf
        write (buf, "(es23.16)") x
        text = trim(adjustl(buf))
    end function real_text

end module mpm_manufactured
