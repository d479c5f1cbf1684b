!> The external loads of a case (`loads`, mpm_case_loads) on the particles.
!>
!> At the start of a run each traction and point load picks the particles that carry it
!> (particles%load, particles%load_share), which then follow the material: a footing's
!> pressure stays on the soil under it as it settles. Every step the loads at the step's time
!> become the particles' extra body force per unit mass (particles%body_force), which P2G
!> scatters to the nodes with the mass and which the energy balance books as load work
!> (motion_type%load_work, sum m b . dx).
module mpm_loads
    use mpm_kinds, only: wp, i8
    use mpm_strings, only: int_text, fmt_real, fmt_vector
    use mpm_error, only: error_type, fatal_error, exit_input
    use mpm_case, only: case_type
    use mpm_case_loads, only: load_traction, load_point, load_body_force
    use mpm_particles, only: particles_type
    use mpm_parallel, only: image_id, sum_over_images, min_over_images, max_over_images
    implicit none
    private
    public :: assign_loads, apply_loads, carried_loads

contains

    !> Whether the case has loads that particles carry (traction, point).
    pure logical function carried_loads(case)
        type(case_type), intent(in) :: case
            !! the case

        integer :: l

        carried_loads = .false.
        if (.not. allocated(case%loads)) return
        do l = 1, size(case%loads)
            if (case%loads(l)%type /= load_body_force) carried_loads = .true.
        end do
    end function carried_loads

    !> The particles that carry each traction and point load, and their shares, at the
    !> start of a run (not a restart: a checkpoint keeps them). Those of a state file are
    !> dropped first: a new stage has its own loads. Collective; the caller agrees on the
    !> error (a particle that two loads claim is found by its image only).
    subroutine assign_loads(case, particles, error)
        type(case_type), intent(in) :: case
            !! the case
        type(particles_type), intent(inout) :: particles
            !! the particles at the start
        type(error_type), allocatable, intent(out) :: error
            !! set when a load finds no particle, or a particle carries two loads

        integer :: l, stat
        character(len=256) :: msg
        type(error_type), allocatable :: this

        if (allocated(particles%load)) deallocate (particles%load)
        if (allocated(particles%load_share)) deallocate (particles%load_share)
        if (.not. carried_loads(case)) return
        allocate (particles%load(particles%n), particles%load_share(particles%n), stat=stat, &
            errmsg=msg)
        if (stat /= 0) then
            call fatal_error(error, "cannot allocate the loads of the particles: "//trim(msg))
            return
        end if
        particles%load = 0
        particles%load_share = 0.0_wp
        ! every image goes through every load (their sums over the images), keeping its first
        ! error: one image's refusal must not leave the others waiting
        do l = 1, size(case%loads)
            select case (case%loads(l)%type)
            case (load_traction)
                call assign_traction(case, l, particles, this)
            case (load_point)
                call assign_point(case, l, particles, this)
            case default
                ! a body force acts on its material's particles (apply_loads)
                continue
            end select
            if (allocated(this) .and. .not. allocated(error)) call move_alloc(this, error)
        end do
    end subroutine assign_loads

    !> A traction's particles (centres in its box) and their shares of its resultant.
    subroutine assign_traction(case, l, particles, error)
        type(case_type), intent(in) :: case
            !! the case
        integer, intent(in) :: l
            !! the load
        type(particles_type), intent(inout) :: particles
            !! the particles
        type(error_type), allocatable, intent(out) :: error
            !! set when the box holds no particle or one carries another load

        real(wp) :: volume, area, lo(3), hi(3)
        integer(i8) :: count
        integer :: p, d, dim
        logical, allocatable :: in(:)

        dim = particles%dim
        associate (load => case%loads(l))
            allocate (in(particles%n))
            volume = 0.0_wp
            count = 0
            lo = huge(1.0_wp)
            hi = -huge(1.0_wp)
            do p = 1, particles%n
                in(p) = all(particles%x(:, p) >= load%xmin(1:dim) .and. &
                    particles%x(:, p) <= load%xmax(1:dim))
                if (.not. in(p)) cycle
                ! (no return before the sums over the images: the others wait in them)
                if (particles%load(p) /= 0 .and. .not. allocated(error)) then
                    call fatal_error(error, refusal(case, l, "its box takes a particle at " &
                        //fmt_vector(particles%x(:, p))//" m that loads["// &
                        int_text(particles%load(p))//"] already loads; a particle carries " &
                        //"one traction or point load"), exit_input)
                end if
                count = count + 1
                volume = volume + particles%volume(p)
                lo(1:dim) = min(lo(1:dim), particles%x(:, p) - particles%lp0(:, p))
                hi(1:dim) = max(hi(1:dim), particles%x(:, p) + particles%lp0(:, p))
            end do
            call sum_over_images(count)
            call sum_over_images(volume)
            do d = 1, dim
                call min_over_images(lo(d))
                call max_over_images(hi(d))
            end do
            if (allocated(error)) return
            if (count == 0) then
                call fatal_error(error, refusal(case, l, "its box min = " &
                    //fmt_vector(load%xmin(1:dim))//" m, max = "//fmt_vector(load%xmax(1:dim)) &
                    //" m holds no particle at the start; the box must take the particles " &
                    //"under the loaded surface (the centres of the top layer)"), exit_input)
                return
            end if
            ! the loaded area: the box's extent along the surface, clipped to the particles'
            area = 1.0_wp
            do d = 1, dim
                if (d == load%normal_axis) cycle
                area = area*(min(load%xmax(d), hi(d)) - max(load%xmin(d), lo(d)))
            end do
            do p = 1, particles%n
                if (.not. in(p)) cycle
                particles%load(p) = l
                particles%load_share(p) = area*particles%volume(p)/volume
            end do
        end associate
    end subroutine assign_traction

    !> A point load's particle: the one nearest to its position (the first in the order of
    !> the images and the particles when several are as near), within one cell.
    subroutine assign_point(case, l, particles, error)
        type(case_type), intent(in) :: case
            !! the case
        integer, intent(in) :: l
            !! the load
        type(particles_type), intent(inout) :: particles
            !! the particles
        type(error_type), allocatable, intent(out) :: error
            !! set when no particle is within a cell or the nearest carries another load

        real(wp) :: nearest, d2
        integer :: p, best, owner, dim

        dim = particles%dim
        associate (load => case%loads(l))
            nearest = huge(1.0_wp)
            best = 0
            do p = 1, particles%n
                d2 = sum((particles%x(:, p) - load%position(1:dim))**2)
                if (d2 < nearest) then
                    nearest = d2
                    best = p
                end if
            end do
            d2 = nearest
            call min_over_images(nearest)
            if (nearest > case%domain%dx**2) then
                call fatal_error(error, refusal(case, l, "no particle lies within one cell (" &
                    //fmt_real(case%domain%dx, 6)//" m) of its position " &
                    //fmt_vector(load%position(1:dim))//" m at the start; a point load acts " &
                    //"on the particle nearest to it"), exit_input)
                return
            end if
            owner = huge(1)
            if (best > 0 .and. d2 == nearest) owner = image_id()
            call min_over_images(owner)
            if (owner /= image_id()) return
            if (particles%load(best) /= 0) then
                call fatal_error(error, refusal(case, l, "the particle nearest to its " &
                    //"position, at "//fmt_vector(particles%x(:, best))//" m, already " &
                    //"carries loads["//int_text(particles%load(best))//"]; a particle " &
                    //"carries one traction or point load"), exit_input)
                return
            end if
            particles%load(best) = l
            particles%load_share(best) = 1.0_wp
        end associate
    end subroutine assign_point

    !> The extra body force per unit mass of every particle at time t: the body forces of
    !> its material and the share of the traction or point load it carries, each times its
    !> time factor. Nothing when the case has no loads.
    subroutine apply_loads(case, particles, t)
        type(case_type), intent(in) :: case
            !! the case
        type(particles_type), intent(inout) :: particles
            !! the particles (body_force set)
        real(wp), intent(in) :: t
            !! time of the step's start [s]

        real(wp), allocatable :: force(:, :)
        real(wp) :: b(3)
        integer :: l, p, nl, dim
        logical :: carried

        if (.not. allocated(case%loads)) return
        nl = size(case%loads)
        if (nl == 0) return
        dim = particles%dim
        allocate (force(3, nl))
        do l = 1, nl
            force(:, l) = case%loads(l)%vector*case%loads(l)%time%factor(t)
        end do
        if (allocated(particles%body_force)) then
            if (size(particles%body_force, 2) /= particles%n) deallocate (particles%body_force)
        end if
        if (.not. allocated(particles%body_force)) allocate (particles%body_force(dim, particles%n))
        carried = allocated(particles%load)
        !$omp parallel do default(none) schedule(static) &
        !$omp shared(case, particles, force, nl, dim, carried) private(p, l, b)
        do p = 1, particles%n
            b = 0.0_wp
            do l = 1, nl
                if (case%loads(l)%type == load_body_force .and. &
                    case%loads(l)%material == particles%material(p)) b = b + force(:, l)
            end do
            if (carried) then
                l = particles%load(p)
                if (l > 0) b = b + force(:, l)*particles%load_share(p)/particles%mass(p)
            end if
            particles%body_force(:, p) = b(1:dim)
        end do
        !$omp end parallel do
    end subroutine apply_loads

    !> The message of a load the particles refuse: "case: loads[l] "name": what".
    pure function refusal(case, l, what) result(message)
        type(case_type), intent(in) :: case
        integer, intent(in) :: l
        character(len=*), intent(in) :: what
        character(len=:), allocatable :: message

        message = case%file//": loads["//int_text(l)//'] "'//case%loads(l)%name//'": '//what
    end function refusal

end module mpm_loads
