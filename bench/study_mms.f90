!> Accuracy against cost on the manufactured solution (REFERENCES.md section 3): every shape
!> function and scheme over a ladder of resolutions, at a large (A = 0.05) and a small
!> (A = 0.001) amplitude. Prints one CSV line per run; `make study` turns them into
!> docs/accuracy-vs-cost.md.
!>
!> Without arguments: the study. The ladder's time step is the CFL step (CFL 0.2), and for
!> USF also the tension step with budget 4 (`tension_time_step`: with FLIP it amplifies
!> particle noise under tension at about sigma dt / (rho0 dx^2); USL and MUSL do not).
!> Then two probes that show why: the manufactured solution at 128 cells against the CFL
!> factor with the CFL step alone (problem "mms_cfl"), and the noise growth of a bar held
!> stretched or compressed at rest (problem "bar").
!>
!> With options: one ladder, for validation/mms/check.py and other scripts:
!>
!>     study_mms --amplitude 0.001 --shapes cpgimp --schemes USL,MUSL --cells 8,16,32,64,128
!>               [--cfl 0.2] [--ppc 2] [--tend 0.02] [--repeat 3] [--tension-budget 4]
!>
!> Exit code 0 (a failed run is a CSV line with status "failed"), 2 for a bad option.
program study_mms
    use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_manufactured, only: mms_result_type, run_manufactured, bar_result_type, &
        run_stretched_bar
    implicit none

    real(wp), parameter :: study_cfl = 0.2_wp
        !! CFL factor of the study [-]
    real(wp), parameter :: study_budget = 4.0_wp
        !! tension budget of USF in the study: noise growth at most about e^4 [-]
    real(wp), parameter :: period = 0.02_wp
        !! one period of the solution, 2 L / c [s]
    real(wp), parameter :: repeat_below = 2.0_wp
        !! runs faster than this are repeated and the fastest kept (noise only adds time) [s]

    type :: ladder_type
        real(wp) :: amplitude = 0.05_wp
        character(len=6), allocatable :: shapes(:)
        character(len=4), allocatable :: schemes(:)
        integer, allocatable :: cells(:)
        real(wp) :: cfl = study_cfl
        integer :: ppc = 2
        real(wp) :: tend = period
        integer :: repeat = 3
        real(wp) :: budget = 0.0_wp
            !! tension budget; 0: the CFL step alone
        logical :: budget_for_musl_usf = .false.
            !! the study's rule: the budget applies to USF only (MUSL moves the particles with
            !! the velocities that strain them since the noise was found)
    end type ladder_type

    type(ladder_type) :: ladder
    logical :: study
    integer :: status

    call parse_options(ladder, study, status)
    if (status /= 0) stop 2
    write (output_unit, "(a)") "problem,amplitude,shape,scheme,cells,particles,steps,wall_s," &
        //"error_l2_m,error_max_m,status,cfl,tension_budget,stress_pa,growth_per_s," &
        //"estimate_per_s"
    if (.not. study) then
        call run_ladder("mms", ladder)
        stop
    end if
    ! the study: both amplitudes, every shape function and scheme, 8 to 256 cells
    ladder%shapes = [character(len=6) :: "linear", "cpgimp"]
    ladder%schemes = [character(len=4) :: "USF", "USL", "MUSL"]
    ladder%cells = [8, 16, 32, 64, 128, 256]
    ladder%budget = study_budget
    ladder%budget_for_musl_usf = .true.
    ladder%amplitude = 0.05_wp
    call run_ladder("mms", ladder)
    ladder%amplitude = 0.001_wp
    call run_ladder("mms", ladder)
    ! probe 1: the large amplitude at 128 cells against the CFL factor, CFL step alone
    ladder%amplitude = 0.05_wp
    ladder%shapes = [character(len=6) :: "cpgimp"]
    ladder%cells = [128]
    ladder%budget = 0.0_wp
    ladder%budget_for_musl_usf = .false.
    ladder%repeat = 1
    ladder%cfl = 0.4_wp
    call run_ladder("mms_cfl", ladder)
    ladder%cfl = 0.2_wp
    call run_ladder("mms_cfl", ladder)
    ladder%cfl = 0.1_wp
    call run_ladder("mms_cfl", ladder)
    ! probe 2: noise growth in a bar held at rest, stretched and compressed
    call run_bars([1.3_wp, 0.7_wp], [128, 256], [0.2_wp, 0.4_wp])

contains

    !> Every shape, scheme and resolution of a ladder, one CSV line each.
    subroutine run_ladder(problem, lad)
        character(len=*), intent(in) :: problem
        type(ladder_type), intent(in) :: lad

        type(mms_result_type) :: r, best
        type(error_type), allocatable :: error
        real(wp) :: budget
        integer :: i, j, k, repeat

        do i = 1, size(lad%shapes)
            do j = 1, size(lad%schemes)
                budget = lad%budget
                if (lad%budget_for_musl_usf .and. trim(lad%schemes(j)) /= "USF") budget = 0.0_wp
                do k = 1, size(lad%cells)
                    best%wall = huge(1.0_wp)
                    do repeat = 1, max(lad%repeat, 1)
                        if (budget > 0.0_wp) then
                            call run_manufactured(lad%cells(k), trim(lad%shapes(i)), &
                                trim(lad%schemes(j)), lad%amplitude, lad%tend, lad%cfl, lad%ppc, &
                                r, error, budget)
                        else
                            call run_manufactured(lad%cells(k), trim(lad%shapes(i)), &
                                trim(lad%schemes(j)), lad%amplitude, lad%tend, lad%cfl, lad%ppc, &
                                r, error)
                        end if
                        if (allocated(error)) exit
                        if (r%wall < best%wall) best = r
                        if (r%wall >= repeat_below) exit
                    end do
                    if (allocated(error)) then
                        write (output_unit, "(a,',',es10.3,5a,i0,a,2(',',es10.3),a)") &
                            problem, lad%amplitude, ",", trim(lad%shapes(i)), ",", &
                            trim(lad%schemes(j)), ",", lad%cells(k), ",,,,,,failed", lad%cfl, &
                            budget, ",,,"
                        write (error_unit, "(a)") error%message
                        deallocate (error)
                        cycle
                    end if
                    write (output_unit, "(a,',',es10.3,5a,3(i0,a),es12.5,2(',',es12.5),a," &
                        //"2(',',es10.3),a)") problem, lad%amplitude, ",", trim(lad%shapes(i)), &
                        ",", trim(lad%schemes(j)), ",", lad%cells(k), ",", best%particles, ",", &
                        best%steps, ",", best%wall, best%error_l2, best%error_max, ",ok", lad%cfl, &
                        budget, ",,,"
                    flush (output_unit)
                end do
            end do
        end do
    end subroutine run_ladder

    !> The stretched or compressed bar at rest, cpGIMP, every scheme: noise growth rate and its
    !> estimate sigma+ dt / (rho0 dx^2), over 4 ms.
    subroutine run_bars(stretches, cells, cfls)
        real(wp), intent(in) :: stretches(:)
        integer, intent(in) :: cells(:)
        real(wp), intent(in) :: cfls(:)

        character(len=*), parameter :: schemes(3) = [character(len=4) :: "USF", "USL", "MUSL"]
        type(bar_result_type) :: r
        type(error_type), allocatable :: error
        integer :: i, j, k, m

        do i = 1, size(stretches)
            do k = 1, size(cells)
                do m = 1, size(cfls)
                    do j = 1, size(schemes)
                        call run_stretched_bar(cells(k), stretches(i), "cpgimp", &
                            trim(schemes(j)), cfls(m), 0.004_wp, r, error)
                        if (allocated(error)) then
                            write (output_unit, "(a,es12.5,3a,i0,a,es10.3,a)") "bar,", &
                                stretches(i), ",cpgimp,", trim(schemes(j)), ",", cells(k), &
                                ",,,,,,failed,", cfls(m), ",,,,"
                            write (error_unit, "(a)") error%message
                            deallocate (error)
                            cycle
                        end if
                        ! the "amplitude" column holds the stretch F of the bar
                        write (output_unit, "(a,es12.5,2a,3(',',i0),',',es12.5,a,es10.3,a," &
                            //"3(',',es12.5))") "bar,", r%stretch, ",cpgimp,", &
                            trim(schemes(j)), cells(k), r%particles, r%steps, r%wall, &
                            ",,,ok,", cfls(m), ",0", r%stress, r%growth, r%estimate
                        flush (output_unit)
                    end do
                end do
            end do
        end do
    end subroutine run_bars

    !> Read the options; study = .true. when there are none.
    subroutine parse_options(lad, study, status)
        type(ladder_type), intent(inout) :: lad
        logical, intent(out) :: study
        integer, intent(out) :: status

        character(len=256) :: key, value
        integer :: i, n, ios

        status = 0
        n = command_argument_count()
        study = n == 0
        lad%shapes = [character(len=6) :: "cpgimp"]
        lad%schemes = [character(len=4) :: "MUSL"]
        lad%cells = [8, 16, 32, 64, 128]
        i = 1
        do while (i <= n)
            call get_command_argument(i, key)
            if (key == "-h" .or. key == "--help") then
                write (output_unit, "(a)") "usage: study_mms [--amplitude A] [--shapes S,..] " &
                    //"[--schemes X,..] [--cells N,..] [--cfl C] [--ppc N] [--tend T] " &
                    //"[--repeat N] [--tension-budget B]  (no option: the whole study)"
                stop
            end if
            if (i == n) then
                write (error_unit, "(a)") "study_mms: option "//trim(key)//" needs a value"
                status = 2
                return
            end if
            call get_command_argument(i + 1, value)
            ios = 0
            select case (key)
            case ("--amplitude")
                read (value, *, iostat=ios) lad%amplitude
            case ("--shapes")
                call split_words(value, lad%shapes)
            case ("--schemes")
                call split_schemes(value, lad%schemes)
            case ("--cells")
                call split_integers(value, lad%cells, ios)
            case ("--cfl")
                read (value, *, iostat=ios) lad%cfl
            case ("--ppc")
                read (value, *, iostat=ios) lad%ppc
            case ("--tend")
                read (value, *, iostat=ios) lad%tend
            case ("--repeat")
                read (value, *, iostat=ios) lad%repeat
            case ("--tension-budget")
                read (value, *, iostat=ios) lad%budget
            case default
                write (error_unit, "(a)") "study_mms: unknown option "//trim(key)//"; see --help"
                status = 2
                return
            end select
            if (ios /= 0) then
                write (error_unit, "(a)") "study_mms: bad value '"//trim(value)//"' for "// &
                    trim(key)
                status = 2
                return
            end if
            i = i + 2
        end do
    end subroutine parse_options

    subroutine split_words(text, words)
        character(len=*), intent(in) :: text
        character(len=6), allocatable, intent(out) :: words(:)
        integer :: start, comma
        allocate (words(0))
        start = 1
        do
            comma = index(text(start:), ",")
            if (comma == 0) then
                words = [character(len=6) :: words, adjustl(text(start:))]
                exit
            end if
            words = [character(len=6) :: words, adjustl(text(start:start + comma - 2))]
            start = start + comma
        end do
    end subroutine split_words

    subroutine split_schemes(text, words)
        character(len=*), intent(in) :: text
        character(len=4), allocatable, intent(out) :: words(:)
        character(len=6), allocatable :: six(:)
        integer :: i
        call split_words(text, six)
        allocate (words(size(six)))
        do i = 1, size(six)
            words(i) = six(i)(1:4)
        end do
    end subroutine split_schemes

    subroutine split_integers(text, values, ios)
        character(len=*), intent(in) :: text
        integer, allocatable, intent(out) :: values(:)
        integer, intent(out) :: ios
        integer :: n, i
        n = 1
        do i = 1, len_trim(text)
            if (text(i:i) == ",") n = n + 1
        end do
        allocate (values(n))
        read (text, *, iostat=ios) values
    end subroutine split_integers

end program study_mms
